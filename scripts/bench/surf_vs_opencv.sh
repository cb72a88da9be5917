#!/usr/bin/env bash
# SURF detect + describe per image, one thread: keylo's `surf` (feature `nonfree`) against
# OpenCV 3.4.2's SURF from Python, on the same real 1024x64 images, in one run
# (docs/results/surf.md).
# Usage: scripts/bench/surf_vs_opencv.sh [IMAGE_DIR] [COUNT] [REPEATS]
#   IMAGE_DIR: 8-bit grey PNGs image_0000.png… (default ../shared/data/tiers_signal).
# Python: KEYLO_SURF_PYTHON, a Python 3.7 with opencv-contrib-python==3.4.2.17 and numpy<1.22
# (default: a venv made here from pyenv's 3.7, target/surf-venv).
set -euo pipefail
cd "$(dirname "$0")/../.."
dir="${1:-../shared/data/tiers_signal}"
count="${2:-200}"
repeats="${3:-3}"
python="${KEYLO_SURF_PYTHON:-target/surf-venv/bin/python}"
if [ ! -x "$python" ]; then
  "$(pyenv root 2> /dev/null || echo ~/.pyenv)/versions/3.7.16/bin/python3.7" -m venv target/surf-venv
  target/surf-venv/bin/pip install -q "opencv-contrib-python==3.4.2.17" "numpy<1.22"
  python=target/surf-venv/bin/python
fi
cargo build -q --release --locked -p keylo-features --features nonfree --example detector_timing
k=$(./target/release/examples/detector_timing "$dir" "$count" surf "describe = true" "$repeats")
c=$("$python" scripts/bench/surf_opencv_timing.py "$dir" "$count" "$repeats")
python3 - "$k" "$c" <<'PY'
import json, sys
k, c = (json.loads(a) for a in sys.argv[1:3])
print(json.dumps({"keylo_ms": round(k["ms_per_image"], 3), "opencv_ms": round(c["ms_per_image"], 3),
                  "keylo_over_opencv": round(k["ms_per_image"] / c["ms_per_image"], 2),
                  "keypoints_keylo": k["keypoints_per_image"], "keypoints_opencv": c["keypoints_per_image"],
                  "opencv": c["tool"]}))
PY
