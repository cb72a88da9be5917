#!/usr/bin/env bash
# keylo's BRIEF and FREAK against opencv-contrib's on the same keypoints (FAST and BRISK) of
# real images: the share of descriptor rows identical bit for bit (docs/results/paper-reproduction.md).
# Usage: scripts/bench/brief_freak_vs_opencv.sh [IMAGE_DIR] [COUNT]
#   IMAGE_DIR: 8-bit grey PNGs image_0000.png... (default ../shared/data/tiers_signal), COUNT 200.
# Python: KEYLO_CONTRIB_PYTHON, one with opencv-contrib-python-headless 4.x (default: a venv
# made here, target/contrib-venv).
set -euo pipefail
cd "$(dirname "$0")/../.."
dir="${1:-../shared/data/tiers_signal}"
count="${2:-200}"
python="${KEYLO_CONTRIB_PYTHON:-target/contrib-venv/bin/python}"
if [ ! -x "$python" ]; then
  python3 -m venv target/contrib-venv
  target/contrib-venv/bin/pip install -q "opencv-contrib-python-headless<5" numpy
  python=target/contrib-venv/bin/python
fi
dump="$(mktemp)"
trap 'rm -f "$dump"' EXIT
"$python" scripts/bench/brief_freak_opencv_dump.py "$dir" "$count" "$dump"
cargo build -q --release --locked -p keylo-features --example brief_freak_vs_opencv
./target/release/examples/brief_freak_vs_opencv "$dir" "$dump"
