#!/usr/bin/env bash
# Whole pipeline, keypoint cloud vs raw cloud, on the same 131k-point frames in one run:
# image → detect → keypoint-neighbourhood → KISS-ICP against raw cloud → KISS-ICP
# (configs/paper/*), odometry frames per second (source reading excluded) and their ratio.
# Usage: scripts/bench/keypoint_vs_raw.sh [DATA] [FRAMES]
#   DATA: any recording keylo reads; default: a simulated OS0-128 (1024×128) lab, written once.
#   KEYLO_BENCH_EXTRA="indoor-superpoint-kiss-icp outdoor-superpoint-kiss-icp" adds configs.
set -euo pipefail
cd "$(dirname "$0")/../.."
frames="${2:-100}"
cargo build -q --release -p keylo-cli
keylo=./target/release/keylo
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
data="${1:-}"
if [ -z "$data" ]; then
  data="$work/lab"
  "$keylo" sim --scene lab --set appearance=ideal --frames "$frames" --out "$data" -q >/dev/null
fi
for cfg in raw-kiss-icp indoor-akaze-kiss-icp outdoor-akaze-kiss-icp ${KEYLO_BENCH_EXTRA:-} "$@"; do
  case "$cfg" in *-kiss-icp) ;; *) continue ;; esac
  "$keylo" run "configs/paper/$cfg.toml" --data "$data" --set source.max_frames="$frames" \
    --set output.on_bad_frame=skip --out "$work/$cfg" -q >/dev/null 2>&1 || true
done
python3 - "$work" <<'PY'
import json, os, sys
work = sys.argv[1]
rows = {}
for name in sorted(os.listdir(work)):
    p = os.path.join(work, name, "summary.json")
    if os.path.exists(p):
        rows[name] = json.load(open(p))
raw = rows.get("raw-kiss-icp")
print(f"{'config':28} {'frames':>6} {'odom Hz':>8} {'x raw':>6} {'points':>8} {'ATE m':>7}  stage ms (image/detect/downsample/register)")
for name, s in rows.items():
    ratio = s["odometry_hz"] / raw["odometry_hz"] if raw else float("nan")
    ate = (s.get("accuracy") or {}).get("ate_rmse_m")
    st = s["stage_ms"]
    print(f"{name:28} {s['frames']:6d} {s['odometry_hz']:8.1f} {ratio:6.2f} {s['mean_cloud_points']:8.0f} "
          f"{ate if ate is not None else float('nan'):7.3f}  "
          f"{st['image']:.2f}/{st['detect']:.2f}/{st['downsample']:.2f}/{st['register']:.2f}")
PY
