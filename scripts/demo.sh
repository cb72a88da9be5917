#!/usr/bin/env bash
# Sets the machine up (scripts/setup.sh) and runs the built-in demo: a simulated OS0-128 in a
# lab, raw cloud → KISS-ICP, with an accuracy table against the simulator's ground truth.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
"$ROOT/target/release/keylo" run "$@"
