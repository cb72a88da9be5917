#!/usr/bin/env bash
# INT8 SuperPoint against FP32 (docs/results/realtime.md, issue 24 item 1), in one run:
#  1. keypoints and time per 1024x64 image on the real TIERS signal images 100-199 (the
#     INT8 model was calibrated on 0-99): share of FP32 keypoints reproduced within 1 px,
#     descriptor difference, ms per image and the speed-up (examples/superpoint_int8.rs);
#  2. the keypoint study's six metrics at both precisions on the same images
#     (`keylo keypoints eval --combos SUPERPOINT`, `[params.superpoint] precision`);
#  3. odometry ATE with each on the real KITTI snippets.
# Usage: scripts/bench/superpoint_int8.sh [OUT] [THREADS]   (~6 min on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-/tmp/superpoint-int8}
threads=${2:-2}
tiers=${TIERS:-../shared/data/tiers_signal}
keylo=${KEYLO:-target/release/keylo}
mkdir -p "$out"
cargo build -q --release -p keylo-features --example superpoint_int8
./target/release/examples/superpoint_int8 "$tiers" 100 100 3 "$threads" | tee "$out/int8_vs_fp32.json"
for p in fp32 int8; do
    printf 'preset = "paper"\n[params.superpoint]\nprecision = "%s"\nthreads = %s\n' "$p" "$threads" > "$out/$p.toml"
    "$keylo" keypoints eval --data "$tiers" --start 100 --frames 100 --combos SUPERPOINT \
        --config "$out/$p.toml" --out "$out/eval-$p" --no-plots -q --jobs 1
done
# 3. Odometry with each: the paper's outdoor SuperPoint pipeline on the two real KITTI snippets
#    (ATE against their reference poses); the simulated sequences are in scripts/bench/realtime.sh.
kitti=${KITTI:-../shared/data/kitti_mini}
for s in 00 01; do
    [ -d "$kitti/$s" ] || continue
    "$keylo" -q compare configs/paper/outdoor-superpoint-kiss-icp.toml --data "$kitti/$s" \
        --gt "$kitti/$s/poses_semantickitti_velo.txt" --grid detector.precision=fp32,int8 \
        --no-plots --out "$out/kitti$s"
    grep -A5 "^## Accuracy" "$out/kitti$s/compare.md"
done
python3 - "$out" <<'PY'
import csv, json, sys, pathlib
out = pathlib.Path(sys.argv[1])
r = json.loads((out / "int8_vs_fp32.json").read_text())
print(f"images {r['first']}..{r['first'] + r['images'] - 1}, {r['threads']} threads: "
      f"FP32 {r['fp32_ms']:.1f} ms, INT8 {r['int8_ms']:.1f} ms per image (x{r['speedup']:.2f}); "
      f"keypoints {r['fp32_keypoints']} / {r['int8_keypoints']}, "
      f"{100 * r['reproduced_within_1px']:.1f} % of FP32's within 1 px")
rows = {p: {r["metric"]: r["median"] for r in csv.DictReader(open(out / f"eval-{p}" / "summary.csv"))}
        for p in ("fp32", "int8")}
print("medians over the images:")
print(f"{'metric':30} {'FP32':>7} {'INT8':>7} {'diff':>7}")
for k in ("keypoints", "robustness_rotation", "robustness_scaling", "robustness_blur",
          "match_ratio", "match_score", "distinctiveness"):
    a, b = float(rows["fp32"][k]), float(rows["int8"][k])
    print(f"{k:30} {a:7.3f} {b:7.3f} {b - a:+7.3f}")
PY
