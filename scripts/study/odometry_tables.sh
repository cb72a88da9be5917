#!/usr/bin/env bash
# Every `keylo compare` behind docs/results/odometry.md (all but the same-budget study, which
# is scripts/study/same_budget.sh): 200-frame simulated lab, corridor and road and a
# 1000-frame lab (default appearance), the real OS0-128 sample and the two KITTI snippets.
# Each command writes OUT/<name>/ (compare.md/.csv/.json, plots); docs/results/odometry/<name>/
# holds the committed copies.
#   bash scripts/study/odometry_tables.sh [OUT]      # OUT defaults to /tmp/odo
set -euo pipefail
cd "$(dirname "$0")/../.."
keylo=${KEYLO:-target/release/keylo}
out=${1:-/tmp/odo}
P=configs/paper
mkdir -p "$out"
for s in lab corridor road; do
    [ -f "$out/$s/gt.tum" ] || "$keylo" -q sim --scene "$s" --set appearance=ideal --frames 200 --out "$out/$s"
done
[ -f "$out/lab1000/gt.tum" ] || "$keylo" -q sim --scene lab --set appearance=ideal --frames 1000 --out "$out/lab1000"
seqs=(--data "$out/lab" --data "$out/corridor" --data "$out/road")
run() { # NAME ARGS...: one compare into OUT/NAME, timed
    local name=$1 start
    shift
    start=$(date +%s)
    "$keylo" -q compare "$@" --jobs 1 --out "$out/$name"
    echo "$name: $(( $(date +%s) - start )) s"
}
# neighbour-size grid (the paper's kissicp-neighbor-evaluate and kiss-points), AKAZE defaults,
# then with the AKAZE response threshold at 1e-4
run neighbour-default $P/raw-kiss-icp.toml $P/indoor-akaze-kiss-icp.toml "${seqs[@]}" \
    --grid k_sig=4,5,7 --grid k_rng=4,5,7
run neighbour $P/raw-kiss-icp.toml $P/indoor-akaze-kiss-icp.toml "${seqs[@]}" \
    --grid detector.threshold=0.0001 --grid k_sig=4,5,7 --grid k_rng=4,5,7
# KISS-ICP performance table, indoor (5_5) and outdoor (4_7) presets
run indoor $P/raw-kiss-icp.toml $P/indoor-akaze-kiss-icp.toml $P/indoor-superpoint-kiss-icp.toml \
    --data "$out/lab" --data "$out/corridor" --grid detector.threshold=0.0001 \
    --grid downsampler.on_too_few=all-points
run outdoor $P/raw-kiss-icp.toml $P/outdoor-akaze-kiss-icp.toml $P/outdoor-superpoint-kiss-icp.toml \
    --data "$out/road"
# the real OS0-128 sample (2 frames, no ground truth)
run real $P/raw-kiss-icp.toml $P/outdoor-akaze-kiss-icp.toml $P/outdoor-superpoint-kiss-icp.toml \
    --data tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap
# NDT, and ICP vs NDT from one command
run ndt-lab $P/raw-ndt.toml $P/indoor-akaze-ndt.toml --data "$out/lab" \
    --grid detector.threshold=0.0001 --grid downsampler.on_too_few=all-points
run ndt-road $P/raw-ndt.toml $P/outdoor-akaze-ndt.toml --data "$out/road"
run icp-ndt-lab $P/raw-kiss-icp.toml $P/indoor-akaze-kiss-icp.toml --data "$out/lab" \
    --grid registrar.kind=kiss-icp,ndt --grid detector.threshold=0.0001 \
    --grid downsampler.on_too_few=all-points
# memory over 1000 frames, keypoints and raw cloud
run rss1000 $P/indoor-akaze-kiss-icp.toml --data "$out/lab1000" --grid detector.threshold=0.0001
run rss1000raw $P/raw-kiss-icp.toml --data "$out/lab1000"
# the KITTI snippets (read from ../shared, outputs not committed)
for s in 00 01; do
    k=../shared/data/kitti_mini/$s
    [ -d "$k" ] || { echo "kitti$s: $k is absent, skipped"; continue; }
    run kitti$s $P/raw-kiss-icp.toml $P/outdoor-akaze-kiss-icp.toml --data "$k" \
        --gt "$k/poses_semantickitti_velo.txt" --grid registrar.kind=kiss-icp,ndt \
        --grid downsampler.on_too_few=all-points
done
