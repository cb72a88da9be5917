#!/usr/bin/env bash
# Memory of a saved global map over a long run (docs/results/maps.md): raw KISS-ICP on the
# simulated road loop (~750 m, ~8 m/s) for FRAMES frames (default 10 000, ~11 laps), without
# a map, with the default tiled map (tiles out of the sensor's reach wait on disk), and with
# one tile that holds everything in memory (map.tile_size = 100 km). Prints the process's
# resident memory at frames 1000, 2500, 5000, 10 000 and its peak, per run.
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
    local name="$1"; shift
    "$BIN" -q run configs/examples/road-raw-kiss-icp.toml --set "source.frames=$FRAMES" \
        --out "$OUT/$name" "$@"
}
run no-map
run tiled --map-out "$OUT/tiled-map"
run one-tile --map-out "$OUT/one-tile-map" --set map.tile_size=100000
python3 - "$OUT" <<'PY'
import csv, json, sys
out = sys.argv[1]
print(f"{'run':10} {'frames':>7} {'rss@1000':>9} {'rss@2500':>9} {'rss@5000':>9} {'rss@10000':>10} {'peak MB':>8} {'map points':>11} {'keyframes':>9} {'Hz':>6}")
for name in ["no-map", "tiled", "one-tile"]:
    rows = list(csv.DictReader(open(f"{out}/{name}/frames.csv")))
    s = json.load(open(f"{out}/{name}/summary.json"))
    at = lambda k: f"{float(rows[k - 1]['rss_mb']):.0f}" if len(rows) >= k else "-"
    m = s.get("map") or {}
    print(f"{name:10} {len(rows):7} {at(1000):>9} {at(2500):>9} {at(5000):>9} {at(10000):>10} "
          f"{s['peak_rss_mb']:8.0f} {m.get('points', '-'):>11} {m.get('keyframes', '-'):>9} {s['wall_hz']:6.1f}")
PY
