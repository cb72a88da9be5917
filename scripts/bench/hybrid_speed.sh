#!/usr/bin/env bash
# Issue 24 item 2: the `hybrid` registrar's odometry rate against raw KISS-ICP's on the same
# frames with the same 0.2 m voxel size (configs/paper/raw-kiss-icp.toml against
# configs/examples/raw-hybrid.toml: the raw cloud plus FAST/FREAK keypoints), one run at a
# time so the rates of one invocation compare. Also prints each run's accuracy (the tables of
# docs/results/hybrid.md). Data: simulated lab, road (100 frames) and corridor (200), the long
# hall, and the KITTI snippets of ../shared/data/kitti_mini (read in place).
#   bash scripts/bench/hybrid_speed.sh [OUT]     # OUT defaults to /tmp/hybrid-speed; ~6 min
set -euo pipefail
cd "$(dirname "$0")/../.."
keylo=${KEYLO:-target/release/keylo}
out=${1:-/tmp/hybrid-speed}
shared=${SHARED:-../shared}
mkdir -p "$out"
P=configs/paper; E=configs/examples
sim() { # name scene frames [--set ...]
    local name=$1 scene=$2 frames=$3; shift 3
    [ -f "$out/$name/gt.tum" ] || "$keylo" -q sim --scene "$scene" --frames "$frames" "$@" --out "$out/$name"
}
sim lab lab 100
sim road road 100
sim corridor corridor 200
sim hall10 corridor 200 --set max_range_m=10
data=(--data "$out/lab" --data "$out/road" --data "$out/corridor" --data "$out/hall10")
"$keylo" -q compare "$P/raw-kiss-icp.toml" "$E/raw-hybrid.toml" "${data[@]}" --no-plots \
    --rerun --out "$out/sim"
for s in 00 01; do
    kitti="$shared/data/kitti_mini/$s"
    [ -d "$kitti" ] || continue
    "$keylo" -q compare "$P/raw-kiss-icp.toml" "$E/raw-hybrid.toml" --data "$kitti" \
        --gt "$kitti/poses_semantickitti_velo.txt" --no-plots --rerun --out "$out/kitti$s"
done
python3 - "$out" <<'PY'
import json, sys, glob, os
out = sys.argv[1]
print("| data | raw KISS-ICP Hz | hybrid Hz | hybrid / raw | ATE RMSE raw (m) | ATE RMSE hybrid (m) |")
print("|---|---:|---:|---:|---:|---:|")
for path in [f"{out}/sim/compare.json"] + sorted(glob.glob(f"{out}/kitti*/compare.json")):
    runs = json.load(open(path))["runs"]
    for data in dict.fromkeys(r["data"] for r in runs):
        by = {r["registrar"]: r for r in runs if r["data"] == data}
        raw, hyb = by.get("kiss-icp"), by.get("hybrid")
        if not raw or not hyb:
            continue
        f = lambda r, k: "–" if r.get(k) is None else f"{r[k]:.3f}"
        label = data if "kitti" not in path else "KITTI " + os.path.basename(os.path.dirname(path))[5:]
        ratio = hyb["odometry_hz"] / raw["odometry_hz"]
        print(f"| {label} | {raw['odometry_hz']:.1f} | {hyb['odometry_hz']:.1f} | {ratio:.2f} | "
              f"{f(raw, 'trans_rmse_m')} | {f(hyb, 'trans_rmse_m')} |")
PY
