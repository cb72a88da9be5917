#!/usr/bin/env bash
# keylo's KISS-ICP vs official KISS-ICP (PRBonn, via ../shared/peers/kiss_icp_reference.sh) on
# the same simulated frames. Writes a Markdown table to stdout and everything else to OUT.
# Usage: scripts/kiss_icp_parity.sh [OUT] [FRAMES] [SEEDS]   (SEEDS: e.g. "0 1 2")
# Needs the peers venv (../shared/peers/setup-venv.sh); not part of CI.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
OUT="${1:-/tmp/keylo-parity}"; FRAMES="${2:-200}"; SEEDS="${3:-0 1 2}"
PEERS="${KEYLO_PEERS:-$ROOT/../shared/peers}"
K="$ROOT/target/release/keylo"
cargo build --release -q -p keylo-cli --manifest-path "$ROOT/Cargo.toml"
mkdir -p "$OUT"
now() { python3 -c 'import time; print(time.time())'; }

# case name | scene | sim settings | keylo registrar settings | upstream config yaml
run_case() {
  local name="$1" scene="$2" sim_sets="$3" reg_sets="$4" yaml="$5"
  local d="$OUT/$name"; rm -rf "$d"; mkdir -p "$d"
  local sets=(); for s in $sim_sets; do sets+=(--set "$s"); done
  "$K" sim -q --scene "$scene" --frames "$FRAMES" --format kitti-bin --out "$d/bin" "${sets[@]}"
  "$K" sim -q --scene "$scene" --frames "$FRAMES" --out "$d/frames" "${sets[@]}"
  local up_args=()
  if [ -n "$yaml" ]; then printf '%b' "$yaml" > "$d/upstream.yaml"; up_args=(--config "$d/upstream.yaml"); fi
  bash "$PEERS/kiss_icp_reference.sh" "$d/bin/velodyne" "$d/upstream" "${up_args[@]}" >&2
  local ksets=(); for s in $reg_sets; do ksets+=(--set "$s"); done
  local t0; t0=$(now)
  "$K" run -q --data "$d/frames" --out "$d/keylo" "${ksets[@]}"
  local t1; t1=$(now)
  python3 -c "print($t1 - $t0)" > "$d/keylo/wall_s.txt"
  "$K" eval --json --est "$d/upstream/kiss_icp_poses_kitti.txt" --gt "$d/bin/gt.tum" > "$d/upstream_vs_gt.txt"
  "$K" eval --json --est "$d/keylo/trajectory.tum" --gt "$d/frames/gt.tum" > "$d/keylo_vs_gt.txt"
  "$K" eval --json --est "$d/keylo/trajectory.kitti" --gt "$d/upstream/kiss_icp_poses_kitti.txt" > "$d/keylo_vs_upstream.txt"
  python3 - "$d" "$name" "$FRAMES" <<'PY'
import json, re, sys
d, name, frames = sys.argv[1], sys.argv[2], int(sys.argv[3])
def acc(f):
    text = open(f"{d}/{f}").read()
    return json.loads(text[text.index("{"):])
up, ke, kvu = acc("upstream_vs_gt.txt"), acc("keylo_vs_gt.txt"), acc("keylo_vs_upstream.txt")
summary = json.load(open(f"{d}/keylo/summary.json"))
up_wall = float(open(f"{d}/upstream/kiss_icp_time.txt").read())
ke_wall = float(open(f"{d}/keylo/wall_s.txt").read())
m = re.search(r"Average Frequency\D*?(\d+(\.\d+)?)", open(f"{d}/upstream/kiss_icp_stdout.txt").read())
up_hz = float(m.group(1)) if m else float("nan")
print(f"| {name} | {frames} | {up['ate_rmse_m']:.4f} | {ke['ate_rmse_m']:.4f} | "
      f"{100*(ke['ate_rmse_m']-up['ate_rmse_m'])/up['ate_rmse_m']:+.1f} % | {kvu['ate_rmse_m']:.4f} | "
      f"{up['rpe_trans_rmse_m']:.4f} / {ke['rpe_trans_rmse_m']:.4f} | "
      f"{up_hz:.0f} / {summary['odometry_hz']:.1f} ({summary['odometry_hz']/up_hz:.2f}x) | "
      f"{frames/up_wall:.1f} / {frames/ke_wall:.1f} ({up_wall/ke_wall:.2f}x) |")
PY
}

echo "| case | frames | ATE upstream (m) | ATE keylo (m) | keylo vs upstream ATE | ATE keylo↔upstream (m) | RPE trans upstream / keylo (m/frame) | odometry Hz upstream / keylo | end-to-end frames/s upstream / keylo |"
echo "|---|---|---|---|---|---|---|---|---|"
for seed in $SEEDS; do
  run_case "road-defaults-s$seed" road "motion_distortion=false seed=$seed" "" ""
  run_case "road-distorted-no-deskew-s$seed" road "seed=$seed" "registrar.deskew=false" ""
  run_case "lab-range30-s$seed" lab "motion_distortion=false seed=$seed" "registrar.max_range=30" "data:\n  max_range: 30.0\n"
done
