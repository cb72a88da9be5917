#!/usr/bin/env bash
# The paper's CPU table, keylo's column (docs/results/realtime.md): the raw cloud and the
# paper's AKAZE and SuperPoint (FP32 and INT8) keypoint clouds with KISS-ICP, each played back at the
# sensor's rate (`keylo compare --realtime`: frames released at their timestamps, 10 Hz),
# so CPU (%) and peak RSS are those at that rate, as the paper measures them.
# Data: the simulated lab (indoor configs) and road (outdoor configs) with the `ouster`
# appearance, FRAMES frames each at 1024×128, and the real OS0-128 sample of
# ../shared/data/ouster (two complete frames: too short for a steady figure, kept for the
# real sensor's image sizes).
#   bash scripts/bench/realtime.sh [OUT]     # OUT defaults to /tmp/realtime; ~4 min
set -euo pipefail
cd "$(dirname "$0")/../.."
keylo=${KEYLO:-target/release/keylo}
out=${1:-/tmp/realtime}
frames=${FRAMES:-150}
shared=${SHARED:-../shared}
mkdir -p "$out"
P=configs/paper
configs() { # indoor|outdoor
    echo "$P/raw-kiss-icp.toml $P/$1-akaze-kiss-icp.toml $P/$1-superpoint-kiss-icp.toml"
}
for scene in lab road; do
    data="$out/$scene-ouster"
    [ -f "$data/gt.tum" ] || "$keylo" -q sim --scene "$scene" --frames "$frames" \
        --set appearance=ouster --out "$data"
    case $scene in lab) io=indoor ;; *) io=outdoor ;; esac
    # shellcheck disable=SC2046
    "$keylo" -q compare $(configs "$io") --data "$data" --realtime --no-plots \
        --grid detector.precision=fp32,int8 --out "$out/cmp-$scene"
    echo "$scene -> $out/cmp-$scene/compare.md"
done
pcap="$shared/data/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap"
if [ -f "$pcap" ]; then
    # shellcheck disable=SC2046
    "$keylo" -q compare $(configs indoor) --data "$pcap" --realtime --no-plots \
        --grid detector.precision=fp32,int8 --out "$out/cmp-os0"
    echo "os0 -> $out/cmp-os0/compare.md"
else
    echo "note: $pcap not found: the real OS0-128 sample is left out" >&2
fi
