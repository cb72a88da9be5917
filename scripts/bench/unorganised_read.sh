#!/usr/bin/env bash
# Reading is not the bottleneck: raw KISS-ICP on a folder of KITTI .bin scans, keylo vs
# official KISS-ICP on the same files, in one run (runs interleaved, REPEATS times, medians).
# Usage: scripts/bench/unorganised_read.sh [SCANS_DIR] [REPEATS]
#   SCANS_DIR: a folder of .bin scans (default: ../shared/data/kitti_mini/00/velodyne; a longer
#   real sequence such as udacity/SFND_3D_Object_Tracking's 78 KITTI raw scans is better)
# Prints per configuration: odometry Hz (downsampler + registrar, from summary.json), the frame
# loop's rate with reading (summary.json wall_hz), the whole command's frames/s, and the read +
# index time per scan (in the loop, and with the image grid as `keylo info` reads it).
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
R = range(1, reps + 1)
med = st.median
up_wall = med([float(open(f"{out}/up{r}/kiss_icp_time.txt").read()) for r in R])
def up_hz(r):
    m = re.search(r"Average Frequency\D*?(\d+(\.\d+)?)", open(f"{out}/up{r}/kiss_icp_stdout.txt").read())
    return float(m.group(1))
up_odo = med([up_hz(r) for r in R])
info_ms = 1e3 * med([float(open(f"{out}/info{r}.txt").read()) for r in R]) / frames
print(f"{data}: {frames} scans, {reps} repeats (interleaved), medians")
print("| run | odometry Hz | loop frames/s | loop / odometry | command frames/s | command vs official KISS-ICP |")
print("|---|---|---|---|---|---|")
print(f"| official KISS-ICP 1.3.0 | {up_odo:.1f} | - | - | {frames / up_wall:.1f} | 1.00x |")
read_ms = {}
for p in (0, 2):
    s = [json.load(open(f"{out}/k{p}-{r}/summary.json")) for r in R]
    wall = med([float(open(f"{out}/k{p}-{r}/wall_s.txt").read()) for r in R])
    odo, loop = med([x["odometry_hz"] for x in s]), med([x["wall_hz"] for x in s])
    read_ms[p] = med([1e3 / x["wall_hz"] - 1e3 / x["odometry_hz"] for x in s])
    label = "keylo, reading in the loop (--prefetch 0)" if p == 0 else "keylo, reading ahead (--prefetch 2, default)"
    print(f"| {label} | {odo:.1f} | {loop:.1f} | {loop / odo:.2f} | {frames / wall:.1f} | {up_wall / wall:.2f}x |")
print()
print(f"- odometry: downsampler + registrar (summary.json odometry_hz); loop: the run's frame loop, "
      f"reading included (summary.json wall_hz); command: the whole command's wall time, start-up "
      f"and output included (for official KISS-ICP: Python start-up too)")
print(f"- reading + indexing in the loop (--prefetch 0): {read_ms[0]:.2f} ms per scan; waiting for "
      f"the reader with --prefetch 2: {read_ms[2]:.2f} ms per scan")
print(f"- reading + indexing with the image grid (`keylo info`, what a keypoint pipeline reads): {info_ms:.2f} ms per scan")
PY
