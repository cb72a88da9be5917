#!/usr/bin/env bash
# The scaling figure of docs/results/scale-out.md: one `keylo keypoints sweep` study (real
# OS0-128 signal images, the paper's combinations, 6 cells) run as 1, 2 and 4 shards on a
# one-node Slurm on this machine (scripts/slurm/cluster.sh), one CPU per shard: wall time from
# submission to the merged tables, and the sum of the shards' own times. Checks that the three
# merged results agree (all but the timing metric), then fits each detector group's cost per
# image against pixels from the per-task times the shards recorded and estimates the paper's
# whole Algorithm-1 grid (5 interpolations × 29 widths × 8 heights × 1146 images).
#
#   bash scripts/slurm/scaling.sh [IMAGES_DIR] > table.md     (~9 min on 2 cores)
# The shards' folders stay in $OUT (default /tmp/keylo-scaling; replaced on each run).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
KEYLO="${KEYLO:-$ROOT/target/release/keylo}"
DATA="$(cd "${1:-$ROOT/../shared/data/tiers_signal}" && pwd)"
IMAGES="${IMAGES:-5}"
[ -x "$KEYLO" ] || { echo "error: $KEYLO: build it first (bash scripts/setup.sh)" >&2; exit 2; }
work="${OUT:-/tmp/keylo-scaling}"
rm -rf "$work"
mkdir -p "$work"
# shellcheck source=cluster.sh
source "$ROOT/scripts/slurm/cluster.sh"
trap 'cluster_stop "$work/cluster"' EXIT
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
    echo "error: the $n-shard study did not complete; logs in $work/s$n/logs" >&2
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
# The figure: wall time and the sum of the shards' times per shard count (SVG, no plotting
# library needed).
counts = sorted(walls)
sums = {n: json.load(open(f"s{n}/merged/merged.json"))["shard_seconds_sum"] for n in counts}
top = max(max(walls.values()), max(sums.values())) * 1.15
W, H, L, B = 560, 340, 60, 50
bar = 36
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="13">',
       f'<rect width="{W}" height="{H}" fill="white"/>',
       f'<text x="{W / 2}" y="22" text-anchor="middle" font-size="15">One keypoint sweep as 1, 2 and 4 Slurm shards (2 cores)</text>']
y = lambda v: H - B - (H - B - 40) * v / top
for t in range(0, int(top) + 1, 50):
    svg.append(f'<line x1="{L}" x2="{W - 20}" y1="{y(t):.1f}" y2="{y(t):.1f}" stroke="#ddd"/>')
    svg.append(f'<text x="{L - 6}" y="{y(t) + 4:.1f}" text-anchor="end">{t}</text>')
svg.append(f'<text x="16" y="{(H - B) / 2 + 20}" transform="rotate(-90 16 {(H - B) / 2 + 20})" text-anchor="middle">seconds</text>')
for i, n in enumerate(counts):
    x0 = L + 40 + i * 150
    for j, (v, colour) in enumerate([(walls[n], "#1f77b4"), (sums[n], "#ff7f0e")]):
        x = x0 + j * (bar + 6)
        svg.append(f'<rect x="{x}" y="{y(v):.1f}" width="{bar}" height="{H - B - y(v):.1f}" fill="{colour}"/>')
        svg.append(f'<text x="{x + bar / 2}" y="{y(v) - 4:.1f}" text-anchor="middle">{v:.0f}</text>')
    svg.append(f'<text x="{x0 + bar + 3}" y="{H - B + 18}" text-anchor="middle">{n} shard{"s" if n > 1 else ""}</text>')
svg.append(f'<rect x="{W - 230}" y="34" width="12" height="12" fill="#1f77b4"/><text x="{W - 212}" y="45">wall time, submit to merged</text>')
svg.append(f'<rect x="{W - 230}" y="52" width="12" height="12" fill="#ff7f0e"/><text x="{W - 212}" y="63">sum of the shards\' own times</text>')
svg.append("</svg>")
open("scaling.svg", "w").write("\n".join(svg) + "\n")
print("| shards | wall time (s) | sum of shard times (s) | speed-up (wall) | tasks |")
print("|---:|---:|---:|---:|---:|")
for n in sorted(walls):
    merged = json.load(open(f"s{n}/merged/merged.json"))
    print(f"| {n} | {walls[n]:.1f} | {merged['shard_seconds_sum']:.1f} | "
          f"{walls[1] / walls[n]:.2f} | {merged['items']} |")
# Per-task seconds (one cell × one detector group) from the 1-shard run. The cost of a group
# grows faster than its pixels (more keypoints to describe and match), so each group's
# seconds per image is fitted as a power law a·MP^k (least squares in log-log).
import math
tasks = json.load(open("s1/shard-0/shard.json"))["results"]
fits = {}
for tid, r in tasks.items():
    interp, size, group = tid.split(" ", 2)
    w, h = map(int, size.split("x"))
    fits.setdefault(group, []).append((w * h / 1e6, r["seconds"] / images))
print()
print("| detector group | cells | s per image at 1024×64 (fit) | exponent k (time ∝ MP^k) |")
print("|---|---:|---:|---:|")
model = {}
for g, pts in sorted(fits.items()):
    xs = [math.log(p) for p, t in pts if t > 0]
    ys = [math.log(t) for p, t in pts if t > 0]
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    k = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else 1.0
    a = math.exp(my - k * mx)
    model[g] = (a, k)
    print(f"| {g} | {n} | {a * (1024 * 64 / 1e6) ** k:.3f} | {k:.2f} |")
widths = range(512, 4097, 128)
heights = range(32, 257, 32)
per_cell = sum(a * (w * h / 1e6) ** k for a, k in model.values() for w in widths for h in heights)
total_s = 5 * per_cell * 1146
core_h = total_s / 3600
print()
print(f"Whole Algorithm-1 grid (5 × {len(widths)} × {len(heights)} cells, 1146 images, "
      f"these {len(model)} detector groups): **{core_h:,.0f} core-hours** "
      f"({5 * len(widths) * len(heights) * len(model):,} shardable tasks; the fits reach "
      f"from {min(p for v in fits.values() for p, _ in v):.2f} to "
      f"{max(p for v in fits.values() for p, _ in v):.2f} MP, the grid to "
      f"{4096 * 256 / 1e6:.2f} MP, so its large cells are extrapolated).")
print()
print("| cluster | wall time, ideal (h) |")
print("|---|---:|")
for nodes, cores in [(1, 2), (1, 64), (8, 64), (32, 64), (128, 64)]:
    print(f"| {nodes} node(s) × {cores} cores | {core_h / (nodes * cores):,.1f} |")
PY
