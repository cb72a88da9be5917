#!/usr/bin/env bash
# The scaling figure of docs/results/scale-out.md: one `keylo keypoints sweep` study (real
# OS0-128 signal images, the paper's combinations, 6 cells) run as 1, 2 and 4 shards on a
# one-node Slurm on this machine (scripts/slurm/cluster.sh), one CPU per shard: wall time from
# submission to the merged tables, and the sum of the shards' own times. Checks that the three
# merged results agree (all but the timing metric), then fits each detector group's cost per
# image against pixels from the per-task times the shards recorded and estimates the paper's
# whole Algorithm-1 grid (5 interpolations × 29 widths × 8 heights × 1146 images).
#
#   bash scripts/slurm/scaling.sh [IMAGES_DIR] > table.md     (~8 min on 2 cores)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
KEYLO="${KEYLO:-$ROOT/target/release/keylo}"
DATA="$(cd "${1:-$ROOT/../shared/data/tiers_signal}" && pwd)"
IMAGES="${IMAGES:-5}"
[ -x "$KEYLO" ] || { echo "error: $KEYLO: build it first (bash scripts/setup.sh)" >&2; exit 2; }
work="$(mktemp -d /tmp/keylo-scaling.XXXXXX)"
# shellcheck source=cluster.sh
source "$ROOT/scripts/slurm/cluster.sh"
trap 'cluster_stop "$work/cluster"; [ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
cluster_start "$work/cluster"
cd "$work"
study=("$KEYLO" keypoints sweep --data "$DATA" --frames "$IMAGES" --combos paper
  --interpolations linear --widths 512,1024,2048 --heights 64,128 --no-plots -q)
finished() { ! scontrol show job "$1" -o 2>/dev/null | grep -qE 'JobState=(PENDING|RUNNING|CONFIGURING|COMPLETING)'; }
for n in 1 2 4; do
  t0=$(date +%s.%N)
  read -r array merge <<< "$(bash "$ROOT/scripts/slurm/submit.sh" "$n" "s$n" -- "${study[@]}")"
  until finished "$merge"; do sleep 0.5; done
  t1=$(date +%s.%N)
  if scontrol show job "$array" -o | grep -o 'JobState=[A-Z]*' | grep -qv COMPLETED ||
     ! scontrol show job "$merge" -o | grep -q 'JobState=COMPLETED'; then
    echo "error: the $n-shard study did not complete; logs in $work/s$n/logs (KEEP=1 keeps them)" >&2
    exit 1
  fi
  echo "$n $t0 $t1" >> walls.txt
  cluster_log "$n shard(s): done in $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s"
done
python3 - "$IMAGES" <<'PY'
import json, sys, glob
images = int(sys.argv[1])
walls = {int(n): float(b) - float(a) for n, a, b in (l.split() for l in open("walls.txt"))}
def results(n):
    r = json.load(open(f"s{n}/merged/sweep.json"))["results"]
    return [dict(x, means=[m for m in x["means"] if m[0] != "time_ms"]) for x in r]
base = results(1)
assert base and all(results(n) == base for n in walls), "merged results differ between shard counts"
print("| shards | wall time (s) | sum of shard times (s) | speed-up (wall) | tasks |")
print("|---:|---:|---:|---:|---:|")
for n in sorted(walls):
    merged = json.load(open(f"s{n}/merged/merged.json"))
    print(f"| {n} | {walls[n]:.1f} | {merged['shard_seconds_sum']:.1f} | "
          f"{walls[1] / walls[n]:.2f} | {merged['items']} |")
# Per-task seconds (one cell × one detector group) from the 1-shard run.
tasks = json.load(open("s1/shard-0/shard.json"))["results"]
fits = {}
for tid, r in tasks.items():
    interp, size, group = tid.split(" ", 2)
    w, h = map(int, size.split("x"))
    fits.setdefault(group, []).append((w * h / 1e6, r["seconds"] / images))
print()
print("| detector group | s per image, fit a + b·megapixels | a (s) | b (s/MP) |")
print("|---|---|---:|---:|")
model = {}
for g, pts in sorted(fits.items()):
    n = len(pts)
    mx = sum(p for p, _ in pts) / n
    my = sum(t for _, t in pts) / n
    sxx = sum((p - mx) ** 2 for p, _ in pts)
    b = sum((p - mx) * (t - my) for p, t in pts) / sxx if sxx > 0 else 0.0
    a = my - b * mx
    model[g] = (a, b)
    print(f"| {g} | {n} cells | {a:.3f} | {b:.2f} |")
widths = range(512, 4097, 128)
heights = range(32, 257, 32)
per_cell = sum(a + b * w * h / 1e6 for a, b in model.values() for w in widths for h in heights)
total_s = 5 * per_cell * 1146
core_h = total_s / 3600
print()
print(f"Whole Algorithm-1 grid (5 × {len(widths)} × {len(heights)} cells, 1146 images, "
      f"these {len(model)} detector groups): **{core_h:,.0f} core-hours** "
      f"({5 * len(widths) * len(heights) * len(model):,} shardable tasks).")
print()
print("| cluster | wall time, ideal (h) |")
print("|---|---:|")
for nodes, cores in [(1, 2), (1, 64), (8, 64), (32, 64), (128, 64)]:
    print(f"| {nodes} node(s) × {cores} cores | {core_h / (nodes * cores):,.1f} |")
PY
