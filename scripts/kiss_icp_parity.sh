#!/usr/bin/env bash
# keylo's KISS-ICP vs official KISS-ICP (PRBonn, via ../shared/peers/kiss_icp_reference.sh) on
# the same input. Writes Markdown tables to stdout and everything else to OUT.
# Usage: scripts/kiss_icp_parity.sh [OUT] [FRAMES] [SEEDS] [PARTS]
#   SEEDS: e.g. "0 1 2"; PARTS: "sim unorganised" (default both)
#   sim:        simulated frames, keylo reading its frame folder, upstream the same points as .bin
#   unorganised: keylo and upstream reading the SAME .bin folders: kitti_mini 00/01 (generic
#               loader, and the KITTI loader's correction + cam0 poses), a synthetic
#               unorganised sequence, unusual layouts made from kitti_mini/00
#               (scripts/bench/odd_layouts.py), and KEYLO_SFND (a folder of real KITTI raw
#               scans, e.g. udacity/SFND_3D_Object_Tracking's 78) when set
# Needs the peers venv (../shared/peers/setup-venv.sh); not part of CI.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
OUT="${1:-/tmp/keylo-parity}"; FRAMES="${2:-200}"; SEEDS="${3:-0 1 2}"; PARTS="${4:-sim unorganised}"
SHARED="${KEYLO_SHARED:-$ROOT/../shared}"
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
  "$K" sim -q --scene "$scene" --set appearance=ideal --frames "$FRAMES" --format kitti-bin --out "$d/bin" "${sets[@]}"
  "$K" sim -q --scene "$scene" --set appearance=ideal --frames "$FRAMES" --out "$d/frames" "${sets[@]}"
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

# One case where both read the same .bin folder DATA. GT: ground truth (TUM/KITTI) or "";
# UP_ARGS: extra kiss_icp_pipeline arguments, or "ref:FILE" to take upstream's poses from FILE
# (no upstream timing then); KSETS: keylo --set values; CAM0: a calib.txt when upstream
# reports cam0 poses (its KITTI loader), "" otherwise.
run_bin_case() {
  local name="$1" data="$2" gt="$3" up_args="$4" ksets_in="$5" cam0="$6"
  local d="$OUT/$name"; rm -rf "$d"; mkdir -p "$d"
  if [[ "$up_args" == ref:* ]]; then
    mkdir -p "$d/upstream"; cp "${up_args#ref:}" "$d/upstream/kiss_icp_poses_kitti.txt"
  else
    # shellcheck disable=SC2086
    bash "$PEERS/kiss_icp_reference.sh" "$data" "$d/upstream" $up_args >&2
  fi
  local ksets=(); for s in $ksets_in; do ksets+=(--set "$s"); done
  local t0; t0=$(now)
  "$K" run -q --data "$data" --out "$d/keylo" "${ksets[@]}" || true
  local t1; t1=$(now)
  python3 -c "print($t1 - $t0)" > "$d/keylo/wall_s.txt"
  local calib=(); [ -n "$cam0" ] && calib=("$cam0")
  python3 "$ROOT/scripts/bench/kitti_pose_diff.py" "$d/keylo/trajectory.kitti" \
    "$d/upstream/kiss_icp_poses_kitti.txt" "${calib[@]}" > "$d/diff.json"
  if [ -n "$gt" ]; then
    # Upstream's KITTI loader reports cam0 poses: compare them with the cam0 ground truth.
    local up_gt="$gt"; [ -n "$cam0" ] && up_gt="${gt/_velo/_cam0}"
    "$K" eval --json --est "$d/upstream/kiss_icp_poses_kitti.txt" --gt "$up_gt" > "$d/upstream_vs_gt.txt" 2>&1 || true
    "$K" eval --json --est "$d/keylo/trajectory.kitti" --gt "$gt" > "$d/keylo_vs_gt.txt" 2>&1 || true
  fi
  python3 - "$d" "$name" <<'PY'
import json, re, sys
d, name = sys.argv[1], sys.argv[2]
def acc(f):
    try:
        text = open(f"{d}/{f}").read()
        return json.loads(text[text.index("{"):])["ate_rmse_m"]
    except (OSError, ValueError, KeyError):
        return None
fmt = lambda v: "-" if v is None else f"{v:.4f}"
diff = json.load(open(f"{d}/diff.json"))
summary = json.load(open(f"{d}/keylo/summary.json"))
frames = summary["frames"]
ke_wall = float(open(f"{d}/keylo/wall_s.txt").read())
up_frames = sum(1 for _ in open(f"{d}/upstream/kiss_icp_poses_kitti.txt"))
try:
    up_wall = float(open(f"{d}/upstream/kiss_icp_time.txt").read())
    m = re.search(r"Average Frequency\D*?(\d+(\.\d+)?)", open(f"{d}/upstream/kiss_icp_stdout.txt").read())
    up_hz = f"{float(m.group(1)):.0f}" if m else "-"
    e2e = f"{up_frames/up_wall:.1f} / {frames/ke_wall:.1f} ({up_wall/ke_wall:.2f}x)"
except OSError:
    up_hz, e2e = "-", f"- / {frames/ke_wall:.1f}"
print(f"| {name} | {frames} / {up_frames} | {summary['mean_cloud_points']:.0f} | "
      f"{summary['frames_predicted']} | {diff['max_dt_m']:.1e} | {diff['max_drot_deg']:.1e} | "
      f"{fmt(acc('upstream_vs_gt.txt'))} / {fmt(acc('keylo_vs_gt.txt'))} | "
      f"{up_hz} / {summary['odometry_hz']:.1f} | {e2e} |")
PY
}

if [[ " $PARTS " == *" sim "* ]]; then
echo "| case | frames | ATE upstream (m) | ATE keylo (m) | keylo vs upstream ATE | ATE keylo↔upstream (m) | RPE trans upstream / keylo (m/frame) | odometry Hz upstream / keylo | end-to-end frames/s upstream / keylo |"
echo "|---|---|---|---|---|---|---|---|---|"
for seed in $SEEDS; do
  run_case "road-defaults-s$seed" road "motion_distortion=false seed=$seed" "" ""
  run_case "road-distorted-no-deskew-s$seed" road "seed=$seed" "registrar.deskew=false" ""
  run_case "lab-range30-s$seed" lab "motion_distortion=false seed=$seed" "registrar.max_range=30" "data:\n  max_range: 30.0\n"
done
fi

if [[ " $PARTS " == *" unorganised "* ]]; then
echo
echo "| case | frames keylo / upstream | points to registrar (mean) | frames predicted | max Δt keylo↔upstream (m) | max Δrot (deg) | ATE vs ground truth upstream / keylo (m) | odometry Hz upstream / keylo | end-to-end frames/s upstream / keylo |"
echo "|---|---|---|---|---|---|---|---|---|"
VENV="$(bash "$PEERS/setup-venv.sh")"
for seq in 00 01; do
  kdir="$SHARED/data/kitti_mini/$seq"
  [ -d "$kdir" ] || { echo "(no $kdir: kitti_mini cases skipped)" >&2; continue; }
  run_bin_case "kitti-$seq-generic" "$kdir/velodyne" "$kdir/poses_semantickitti_velo.txt" "" "" ""
  # The KITTI loader's poses: the committed reference (kiss-icp 1.3.0's KITTI loader no
  # longer finishes with today's numpy: it fails writing its TUM file).
  run_bin_case "kitti-$seq-kitti-loader" "$kdir" "$kdir/poses_semantickitti_velo.txt" \
    "ref:$kdir/reference_kiss_icp_1.3.0_poses_cam0.txt" "source.vertical_angle_correction_deg=0.205" "$kdir/calib.txt"
done
syn="$OUT/synthetic-unorganised"
if [ ! -d "$syn/velodyne" ]; then
  "$K" sim -q --scene road --set appearance=ideal --frames "$FRAMES" --format kitti-bin --out "$syn" \
    --set columns=2048 --set motion_distortion=false --set seed=0
fi
run_bin_case "synthetic-os0-128x2048-road" "$syn/velodyne" "$syn/gt.tum" "" "" ""
odd="$OUT/odd-layouts"
if [ -d "$SHARED/data/kitti_mini/00" ]; then
  [ -d "$odd/zeros" ] || "$VENV/bin/python" "$ROOT/scripts/bench/odd_layouts.py" "$SHARED/data/kitti_mini/00/velodyne" "$odd"
  for c in nonfinite zeros empty-scan one-point one-point-far; do
    run_bin_case "kitti-00-$c" "$odd/$c" "" "" "" ""
  done
fi
if [ -n "${KEYLO_SFND:-}" ]; then
  run_bin_case "kitti-raw-sfnd-78" "$KEYLO_SFND" "" "" "" ""
fi
fi
