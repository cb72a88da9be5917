#!/usr/bin/env bash
# The keypoint study of docs/results/keypoints.md ("Keypoint evaluation"): `keylo keypoints
# eval` on real Ouster frames, real KITTI scans and simulated sequences, with the paper's
# medians beside ours, plus the throughput figures. Usage: scripts/bench/keypoint_eval.sh [OUT]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
OUT="${1:-$ROOT/runs/keypoint-eval}"
K="$ROOT/target/release/keylo"
SHARED="${KEYLO_SHARED:-$ROOT/../shared}"
PAPER="$SHARED/paper/paper-figure-medians.tsv"
CLASSIC=AKAZE_AKAZE,BRISK_BRIEF,BRISK_BRISK,BRISK_FREAK,BRISK_SIFT,FAST_BRIEF,FAST_BRISK,FAST_FREAK,FAST_SIFT,HARRIS_BRIEF,HARRIS_BRISK,HARRIS_FREAK,HARRIS_SIFT,ORB_ORB,SHITOMASI_BRIEF,SHITOMASI_BRISK,SHITOMASI_FREAK,SHITOMASI_SIFT,SIFT_BRIEF,SIFT_BRISK,SIFT_FREAK,SIFT_SIFT
mkdir -p "$OUT"
cargo build --release -p keylo-cli -q --manifest-path "$ROOT/Cargo.toml"
for scene in lab corridor road; do
  [ -d "$OUT/sim-$scene" ] || "$K" sim --scene "$scene" --set appearance=ideal --frames 100 --out "$OUT/sim-$scene" -q
done
t() { /usr/bin/time -f "%e s wall, %M KB peak RSS" "$@"; }
echo "== real OS0-128 signal, 2 frames (1 pair), paper combinations"
t "$K" keypoints eval --data "$SHARED/data/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap" \
  --combos paper --paper "$PAPER" --out "$OUT/os0" -q
echo "== real KITTI 00 (10 scans projected to 64x2048 images; signal = intensity)"
t "$K" keypoints eval --data "$SHARED/data/kitti_mini/00" --combos paper --paper "$PAPER" \
  --out "$OUT/kitti00" -q || true
for scene in lab corridor road; do
  echo "== simulated $scene, 100 frames, paper combinations"
  t "$K" keypoints eval --data "$OUT/sim-$scene" --combos paper --paper "$PAPER" --out "$OUT/$scene" -q
done
echo "== throughput: the 22 classic paper combinations on 100 simulated frames"
t "$K" keypoints eval --data "$OUT/sim-lab" --combos "$CLASSIC" --out "$OUT/classic-lab" --no-plots -q
echo "== throughput: all valid combinations on 100 simulated frames"
t "$K" keypoints eval --data "$OUT/sim-lab" --combos all --out "$OUT/all-lab" --no-plots -q
echo "== sweep throughput: 5 interpolations x widths 512:2048:512 x heights 32:128:32, 10 frames, 4 combinations"
t "$K" keypoints sweep --data "$OUT/sim-lab" --frames 10 --combos AKAZE_AKAZE,ORB_ORB,SHITOMASI_BRIEF,FAST_FREAK \
  --widths 512:2048:512 --heights 32:128:32 --out "$OUT/sweep" -q
for d in os0 kitti00 lab corridor road classic-lab all-lab; do
  [ -f "$OUT/$d/summary.md" ] && grep -E "images \(" "$OUT/$d/summary.md" | sed "s/^/$d: /"
done
grep -E "image evaluations" "$OUT/sweep/sweep.md" || true
