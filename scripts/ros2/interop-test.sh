#!/usr/bin/env bash
# keylo's ROS 2 node against Eclipse Cyclone DDS (PyPI cyclonedds, its C library in the wheel)
# in a private network namespace: scans published by an independent peer, odometry checked
# against `keylo run` on the same scans (scripts/ros2/interop.py, docs/ros2.md).
#
#   scripts/ros2/interop-test.sh [INTEROP_ARGS...]    e.g. --kitti ../shared/data/kitti_mini/00
#
# KEYLO_ROS2_VENV: the environment (default target/ros2-venv); KEYLO_BIN: the keylo binary
# (default target/debug/keylo, built when missing).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
VENV="${KEYLO_ROS2_VENV:-$ROOT/target/ros2-venv}"
BIN="${KEYLO_BIN:-$ROOT/target/debug/keylo}"
cd "$ROOT"
if [ ! -x "$VENV/bin/python" ]; then
    python3 -m venv "$VENV"
fi
"$VENV/bin/pip" install -q --disable-pip-version-check "cyclonedds>=11,<12" "rosbags>=0.10,<0.12" \
    "mcap>=1.2,<2" "mcap-protobuf-support>=0.5" "numpy>=1.24"
if [ ! -x "$BIN" ]; then
    cargo build -q --locked -p keylo-cli
fi
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
bash scripts/ros2/netns.sh "$VENV/bin/python" scripts/ros2/interop.py --keylo "$BIN" --work "$WORK" "$@"
# The live Ouster source inside the node: a real capture replayed over UDP by a Python sender
# (whole, then 5 % of the datagrams dropped), odometry equal to `keylo run` on the capture.
bash scripts/ros2/netns.sh "$VENV/bin/python" scripts/ros2/live_ouster.py --keylo "$BIN" --work "$WORK/live"
