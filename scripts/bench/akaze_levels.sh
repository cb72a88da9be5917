#!/usr/bin/env bash
# AKAZE detect + describe per image on one thread: OpenCV's AKAZE at its defaults against
# keylo's `akaze` (only the scale levels the image size can use), on the same real OS0-128
# signal images in one run; also whether every image's keypoints and descriptors are
# identical (docs/results/akaze.md).
# Usage: scripts/bench/akaze_levels.sh [IMAGE_DIR] [COUNT]
#   IMAGE_DIR: 8-bit grey PNGs image_0000.png… (default: the paper's images,
#   ../shared/data/tiers_signal); COUNT: how many (default 600).
set -euo pipefail
cd "$(dirname "$0")/../.."
dir="${1:-../shared/data/tiers_signal}"
count="${2:-600}"
cargo build -q --release --locked -p keylo-features --example akaze_timing
for size in "1024 64" "2048 128"; do
  # shellcheck disable=SC2086
  ./target/release/examples/akaze_timing "$dir" "$count" $size
done
