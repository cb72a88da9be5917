#!/usr/bin/env bash
# Memory of a saved global map over a long run (docs/results/maps.md): raw KISS-ICP on the
# simulated road loop (~750 m, ~8 m/s) for FRAMES frames (default 10 000, ~11 laps), without
# a map, with the default tiled map (tiles out of the sensor's reach go to disk, and all of
# them when the voxels in memory pass map.memory_mb), and, for the first ONE_TILE_FRAMES
# frames (default 2000), with one tile that holds everything in memory (map.tile_size =
# 100 km, no memory budget). Prints the process's resident memory at frames 1000, 1700,
# 2500, 5000, 10 000 and its peak (per frame, from frames.csv), per run. Memory only: the
# three runs' speeds are not comparable unless the machine is otherwise idle.
#
#   scripts/bench/map_memory.sh OUT_DIR [FRAMES]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
OUT="${1:?usage: map_memory.sh OUT_DIR [FRAMES]}"
FRAMES="${2:-10000}"
BIN="$ROOT/target/release/keylo"
cd "$ROOT"
cargo build -q --release --locked -p keylo-cli
mkdir -p "$OUT"
run() {
    local name="$1" frames="$2"; shift 2
    "$BIN" -q run configs/examples/road-raw-kiss-icp.toml --set "source.frames=$frames" \
        --out "$OUT/$name" "$@"
}
run no-map "$FRAMES"
run tiled "$FRAMES" --map-out "$OUT/tiled-map"
run one-tile "${ONE_TILE_FRAMES:-2000}" --map-out "$OUT/one-tile-map" --set map.tile_size=100000 \
    --set map.memory_mb=1000000
python3 - "$OUT" <<'PY'
import csv, json, sys
out = sys.argv[1]
print(f"{'run':10} {'frames':>7} {'rss@1000':>9} {'rss@1700':>9} {'rss@2500':>9} {'rss@5000':>9} {'rss@10000':>10} {'peak MB':>8} {'map points':>11} {'keyframes':>9}")
for name in ["no-map", "tiled", "one-tile"]:
    rows = list(csv.DictReader(open(f"{out}/{name}/frames.csv")))
    s = json.load(open(f"{out}/{name}/summary.json"))
    rss = [float(r["rss_mb"]) for r in rows]
    at = lambda k: f"{rss[k - 1]:.0f}" if len(rss) >= k else "-"
    m = s.get("map") or {}
    print(f"{name:10} {len(rows):7} {at(1000):>9} {at(1700):>9} {at(2500):>9} {at(5000):>9} {at(10000):>10} "
          f"{max(rss):8.0f} {m.get('points', '-'):>11} {m.get('keyframes', '-'):>9}")
PY
