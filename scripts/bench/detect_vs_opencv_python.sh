#!/usr/bin/env bash
# Detect (+ describe) time per detector/descriptor combination: keylo vs OpenCV from Python,
# on the same 1024x64 real Ouster signal images with the same parameters, in one run.
# Usage: scripts/bench/detect_vs_opencv_python.sh [REPEATS] [INPUT...]
# INPUT: a PCAP (its frames' signal images) or DIR:COUNT (the first COUNT image_NNNN.png of
# DIR, e.g. ../shared/data/tiers_signal:200, the paper's images). Default: the OS-0-128 and
# OS-2-128 samples with signal images: 3 frames.
# Python: KEYLO_CV_PYTHON (default /usr/bin/python3, which needs Debian's python3-opencv:
# the same OpenCV 4.6 keylo links, so the ratio is keylo's overhead).
set -euo pipefail
cd "$(dirname "$0")/../.."
repeats="${1:-50}"
shift || true
if [ "$#" -eq 0 ]; then
  set -- tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap \
    tests/fixtures/ouster/OS-2-128-U1_v2.3.0_1024x10.pcap
fi
python="${KEYLO_CV_PYTHON:-/usr/bin/python3}"
images="$(mktemp -d)"
trap 'rm -rf "$images"' EXIT
cargo build -q --release -p keylo-features --example detect_timing
keylo_json=$(./target/release/examples/detect_timing "$images" "$repeats" "$@")
cv_json=$("$python" scripts/bench/opencv_python_detect_timing.py "$images" "$repeats")
# keylo raises glibc's mmap/trim thresholds for OpenCV's scratch buffers (keep_native_heap);
# the same tunables for Python separate that from the binding's own overhead.
tuned_json=$(GLIBC_TUNABLES=glibc.malloc.mmap_threshold=67108864:glibc.malloc.trim_threshold=268435456 \
  "$python" scripts/bench/opencv_python_detect_timing.py "$images" "$repeats")
python3 - "$keylo_json" "$cv_json" "$tuned_json" <<'PY'
import json, sys
k, c, t = (json.loads(a) for a in sys.argv[1:4])
print(f"images: {k['images']} (keylo) / {c['images']} ({c['tool']})")
print(f"{'combination':18} {'keylo ms':>9} {'python ms':>10} {'ratio':>6} {'py tuned':>9} {'ratio':>6} {'kp keylo':>9} {'kp python':>9}")
for name, ms in k["ms_per_image"].items():
    p, pt = c["ms_per_image"][name], t["ms_per_image"][name]
    print(f"{name:18} {ms:9.3f} {p:10.3f} {ms / p:6.2f} {pt:9.3f} {ms / pt:6.2f} "
          f"{k['keypoints_per_image'][name]:9.1f} {c['keypoints_per_image'][name]:9.1f}")
PY
