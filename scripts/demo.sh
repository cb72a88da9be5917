#!/usr/bin/env bash
# Sets the machine up (scripts/setup.sh) and runs the built-in demo: a simulated OS0-128 in a
# lab, raw cloud → KISS-ICP, with an accuracy table against the simulator's ground truth, then
# `keylo report` of the run (runs/demo-*/report.html: open it in a browser).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
KEYLO="$ROOT/target/release/keylo"
if [ "$#" -gt 0 ]; then
  "$KEYLO" run "$@"
  exit
fi
# No arguments: the built-in demo, with pictures of every 25th frame, and its report page.
OUT="runs/demo-$(date -u +%Y%m%d-%H%M%S)"
"$KEYLO" run --out "$OUT" --images 25
"$KEYLO" report "$OUT"
