#!/usr/bin/env bash
# `keylo ros2` latency and throughput against a Cyclone DDS peer, in a private network
# namespace (docs/results/ros2.md). Release build; the peer's venv as scripts/ros2/interop-test.sh.
#
#   scripts/bench/ros2_latency.sh OUT_DIR [KITTI_SEQUENCE_DIR]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
OUT="${1:?usage: ros2_latency.sh OUT_DIR [KITTI_SEQUENCE_DIR]}"
KITTI="${2:-}"
VENV="${KEYLO_ROS2_VENV:-$ROOT/target/ros2-venv}"
BIN="$ROOT/target/release/keylo"
cd "$ROOT"
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/pip" install -q --disable-pip-version-check "cyclonedds>=11,<12" "rosbags>=0.10,<0.12" \
    "mcap>=1.2,<2" "numpy>=1.24"
cargo build -q --release --locked -p keylo-cli
mkdir -p "$OUT"
# A simulated OS0-128 (128 x 1024) in the lab: 1000 frames for the 10 Hz stream.
if [ ! -f "$OUT/lab/velodyne/000999.bin" ]; then
    "$BIN" -q sim --scene lab --frames 1000 --set appearance=ouster --format kitti-bin --out "$OUT/lab"
fi
run() { bash scripts/ros2/netns.sh "$VENV/bin/python" scripts/bench/ros2_latency.py --keylo "$BIN" --work "$OUT" "$@"; }
if [ -n "$KITTI" ]; then
    run --name kitti --bins "$KITTI" --count 10 | tee "$OUT/kitti.json"
fi
run --name lab --bins "$OUT/lab" --count 50 --stream-count "${STREAM:-1000}" | tee "$OUT/lab.json"
# Memory over 10 000 clouds: the same node flooded with 1000 and with 10 000 clouds (20 000
# points each, as fast as the peer writes them); its peak RSS must not grow with the count.
run --name lab --bins "$OUT/lab" --count 0 --flood 1000 10000 | tee "$OUT/flood.json"
