#!/usr/bin/env bash
# Sets the machine up (scripts/setup.sh, and Chromium for the report's browser test) and runs
# every test of the workspace.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
# Headless Chromium for the test that opens `keylo report`'s page (docs/report.md).
bash "$ROOT/scripts/setup-browser.sh"
cd "$ROOT"
cargo test --workspace --locked

# The Python package and its pytest suite (docs/python.md).
bash "$ROOT/scripts/python-test.sh"
