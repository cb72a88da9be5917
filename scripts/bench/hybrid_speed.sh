#!/usr/bin/env bash
# Issue 24 item 2: the `hybrid` registrar's odometry rate against raw KISS-ICP's on the same
# frames with the same 0.2 m voxel size (configs/paper/raw-kiss-icp.toml against
# configs/examples/raw-hybrid.toml: the raw cloud plus FAST/FREAK keypoints), one run at a
# time, REPEATS (default 3) passes over everything; each rate is the best of its passes (the
# machines are noisy: single runs of the same config differ by up to 1.5×), so the rates of
# one invocation compare. Also prints each run's accuracy (the tables of
# docs/results/hybrid.md; identical in every pass). Data: simulated lab, road (100 frames)
# and corridor (200), the long hall, and the KITTI snippets of ../shared/data/kitti_mini.
#   bash scripts/bench/hybrid_speed.sh [OUT]     # OUT defaults to /tmp/hybrid-speed; ~15 min
set -euo pipefail
cd "$(dirname "$0")/../.."
keylo=${KEYLO:-target/release/keylo}
out=${1:-/tmp/hybrid-speed}
shared=${SHARED:-../shared}
mkdir -p "$out"
P=configs/paper; E=configs/examples
sim() { # name scene frames [--set ...]
    local name=$1 scene=$2 frames=$3; shift 3
    [ -f "$out/$name/gt.tum" ] || "$keylo" -q sim --scene "$scene" --set appearance=ideal --frames "$frames" "$@" --out "$out/$name"
}
sim lab lab 100
sim road road 100
sim corridor corridor 200
sim hall10 corridor 200 --set max_range_m=10
data=(--data "$out/lab" --data "$out/road" --data "$out/corridor" --data "$out/hall10")
for pass in $(seq 1 "${REPEATS:-3}"); do
    "$keylo" -q compare "$P/raw-kiss-icp.toml" "$E/raw-hybrid.toml" "${data[@]}" --no-plots \
        --rerun --out "$out/pass$pass/sim"
    for s in 00 01; do
        kitti="$shared/data/kitti_mini/$s"
        [ -d "$kitti" ] || continue
        "$keylo" -q compare "$P/raw-kiss-icp.toml" "$E/raw-hybrid.toml" --data "$kitti" \
            --gt "$kitti/poses_semantickitti_velo.txt" --no-plots --rerun --out "$out/pass$pass/kitti$s"
    done
done
python3 - "$out" <<'PY'
import json, sys, glob, os
out = sys.argv[1]
best = {}
for path in sorted(glob.glob(f"{out}/pass*/*/compare.json")):
    kitti = os.path.basename(os.path.dirname(path))
    for r in json.load(open(path))["runs"]:
        label = r["data"] if not kitti.startswith("kitti") else "KITTI " + kitti[5:]
        key = (label, r["registrar"])
        if key not in best or r["odometry_hz"] > best[key]["odometry_hz"]:
            best[key] = r
passes = len(glob.glob(f"{out}/pass*"))
print(f"| data | raw KISS-ICP Hz | hybrid Hz | hybrid / raw | ATE RMSE raw (m) | ATE RMSE hybrid (m) |")
print("|---|---:|---:|---:|---:|---:|")
for label in dict.fromkeys(k[0] for k in best):
    raw, hyb = best.get((label, "kiss-icp")), best.get((label, "hybrid"))
    if not raw or not hyb:
        continue
    f = lambda r, k: "–" if r.get(k) is None else f"{r[k]:.3f}"
    ratio = hyb["odometry_hz"] / raw["odometry_hz"]
    print(f"| {label} | {raw['odometry_hz']:.1f} | {hyb['odometry_hz']:.1f} | {ratio:.2f} | "
          f"{f(raw, 'trans_rmse_m')} | {f(hyb, 'trans_rmse_m')} |")
print(f"\nBest of {passes} passes per rate.")
PY
