#!/usr/bin/env bash
# Reading an Ouster capture (decode + batch + destagger + XYZ): keylo vs ouster-sdk (Python),
# both on the same pcap in one run; prints both timings and the ratio.
# Usage: scripts/bench/ouster_vs_sdk.sh [PCAP] [REPEATS]
# Needs the peers venv (../shared/peers/setup-venv.sh) for ouster-sdk.
set -euo pipefail
cd "$(dirname "$0")/../.."
pcap="${1:-tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap}"
repeats="${2:-30}"
python="${KEYLO_PEERS_PYTHON:-$HOME/.cache/keylo-peers/venv/bin/python}"
cargo build -q --release -p keylo-io --example ouster_decode_timing
keylo_json=$(./target/release/examples/ouster_decode_timing "$pcap" "$repeats")
sdk_json=$("$python" scripts/bench/ouster_sdk_timing.py "$pcap" "$repeats")
echo "$keylo_json"
echo "$sdk_json"
python3 - "$keylo_json" "$sdk_json" <<'PY'
import json, sys
k, s = json.loads(sys.argv[1]), json.loads(sys.argv[2])
print(f"frames: keylo {k['frames']}, ouster-sdk {s['frames']}")
print(f"ms per frame: keylo {k['ms_per_frame']:.2f}, ouster-sdk {s['ms_per_frame']:.2f}")
print(f"speed-up per frame (ouster-sdk / keylo): {s['ms_per_frame'] / k['ms_per_frame']:.2f}x")
print(f"open (metadata + XYZ table) ms: keylo {k['open_ms']:.2f}, ouster-sdk {s['open_ms']:.2f}")
PY
