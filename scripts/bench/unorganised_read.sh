#!/usr/bin/env bash
# Reading is not the bottleneck: raw KISS-ICP on a folder of KITTI .bin scans, keylo vs
# official KISS-ICP on the same files, in one run (runs interleaved, REPEATS times, medians).
# Usage: scripts/bench/unorganised_read.sh [SCANS_DIR] [REPEATS]
#   SCANS_DIR: a folder of .bin scans (default: ../shared/data/kitti_mini/00/velodyne; a longer
#   real sequence such as udacity/SFND_3D_Object_Tracking's 78 KITTI raw scans is better)
# Prints per configuration: odometry Hz (downsampler + registrar, from summary.json), end-to-end
# frames/s (wall time of the whole command), and the read + index time per scan measured
# alone (`keylo info`, which reads and indexes every scan and nothing else).
# Needs the peers venv (../shared/peers/setup-venv.sh) for official KISS-ICP; not part of CI.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
DATA="${1:-$ROOT/../shared/data/kitti_mini/00/velodyne}"
REPEATS="${2:-5}"
PEERS="${KEYLO_PEERS:-$ROOT/../shared/peers}"
K="$ROOT/target/release/keylo"
cargo build --release -q -p keylo-cli --manifest-path "$ROOT/Cargo.toml"
OUT="$(mktemp -d)"; trap 'rm -rf "$OUT"' EXIT
now() { python3 -c 'import time; print(time.time())'; }
frames=$(find "$DATA" -maxdepth 1 -name '*.bin' | wc -l)
for r in $(seq "$REPEATS"); do
  bash "$PEERS/kiss_icp_reference.sh" "$DATA" "$OUT/up$r" > /dev/null 2>&1
  for p in 0 2; do
    t0=$(now); "$K" run -q --prefetch "$p" --data "$DATA" --out "$OUT/k$p-$r"; t1=$(now)
    python3 -c "print($t1 - $t0)" > "$OUT/k$p-$r/wall_s.txt"
  done
  t0=$(now); "$K" info "$DATA" > /dev/null; t1=$(now)
  python3 -c "print($t1 - $t0)" > "$OUT/info$r.txt"
done
python3 - "$OUT" "$REPEATS" "$frames" "$DATA" <<'PY'
import json, re, statistics as st, sys
out, reps, frames, data = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
med = lambda xs: st.median(xs)
up_wall = med([float(open(f"{out}/up{r}/kiss_icp_time.txt").read()) for r in range(1, reps + 1)])
def up_hz(r):
    m = re.search(r"Average Frequency\D*?(\d+(\.\d+)?)", open(f"{out}/up{r}/kiss_icp_stdout.txt").read())
    return float(m.group(1))
up_odo = med([up_hz(r) for r in range(1, reps + 1)])
info_ms = 1e3 * med([float(open(f"{out}/info{r}.txt").read()) for r in range(1, reps + 1)]) / frames
print(f"{data}: {frames} scans, {reps} repeats, medians")
print(f"read + index per scan, alone (keylo info): {info_ms:.2f} ms")
print("| run | odometry Hz | end-to-end frames/s | end-to-end vs odometry | end-to-end vs official KISS-ICP |")
print("|---|---|---|---|---|")
print(f"| official KISS-ICP 1.3.0 | {up_odo:.1f} | {frames / up_wall:.1f} | {frames / up_wall / up_odo:.2f} | 1.00x |")
for p in (0, 2):
    s = [json.load(open(f"{out}/k{p}-{r}/summary.json")) for r in range(1, reps + 1)]
    wall = med([float(open(f"{out}/k{p}-{r}/wall_s.txt").read()) for r in range(1, reps + 1)])
    odo = med([x["odometry_hz"] for x in s])
    e2e = frames / wall
    label = "keylo, reading in the loop (--prefetch 0)" if p == 0 else "keylo, reading ahead (--prefetch 2, default)"
    print(f"| {label} | {odo:.1f} | {e2e:.1f} | {e2e / odo:.2f} | {e2e / (frames / up_wall):.2f}x |")
odo0 = med([json.load(open(f"{out}/k0-{r}/summary.json"))["odometry_hz"] for r in range(1, reps + 1)])
print(f"read + index share of a frame (alone / (alone + odometry at --prefetch 0)): "
      f"{info_ms / (info_ms + 1e3 / odo0) * 100:.1f} %")
PY
