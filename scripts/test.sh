#!/usr/bin/env bash
# Sets the machine up (scripts/setup.sh without its release build: the tests build what they
# run; and Chromium for the report's browser test) and runs every test of the workspace.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/setup.sh" --no-release-build
# Headless Chromium for the test that opens `keylo report`'s page (docs/report.md).
bash "$ROOT/scripts/setup-browser.sh"
# Where Chromium is there, its test must run, not skip (crates/keylo-cli/tests/report.rs).
if command -v chromium >/dev/null 2>&1; then export KEYLO_REQUIRE_BROWSER=1; fi
cd "$ROOT"
cargo test --workspace --locked
# SURF, behind the cargo feature `nonfree` (off by default; docs/keypoints.md, "SURF"): its
# tests against OpenCV's own SURF (the golden fixture) and the kpeval combinations with it.
cargo test --locked -p keylo-features --features nonfree --lib --test surf

# The Python package and its pytest suite (docs/python.md).
bash "$ROOT/scripts/python-test.sh"

# The ROS 2 node against an independent DDS implementation (Cyclone DDS), inside a private
# network namespace (docs/ros2.md).
bash "$ROOT/scripts/ros2/interop-test.sh"

# The live view received by an independent client of the Foxglove WebSocket protocol (npm's
# @foxglove/ws-protocol), and viewers that hang or go away (docs/report.md, "Watching a run
# live"). TCP on 127.0.0.1 only.
bash "$ROOT/scripts/view/live-test.sh"
