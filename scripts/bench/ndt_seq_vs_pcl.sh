#!/usr/bin/env bash
# Frame-to-previous-frame NDT odometry, keylo vs PCL 1.13, on a folder of KITTI .bin frames
# (e.g. `keylo sim --scene road --frames 20 --format kitti-bin --out /tmp/road`): the largest
# pose difference along the sequence and the mean ms per alignment of each, in one run.
#   scripts/bench/ndt_seq_vs_pcl.sh DIR [pcl_ndt options, e.g. --res 1.0 --voxel 0.25]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
dir="$1"; shift
pcl="$(bash "$root/../shared/peers/pcl_ndt/build.sh")"
cargo build -q --release -p keylo-registration --example ndt_pair --manifest-path "$root/Cargo.toml"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
p="$("$pcl" seq "$dir" "$tmp/pcl.tum" "$@" 2>/dev/null | awk '{print $4}')"
k="$("$root/target/release/examples/ndt_pair" seq "$dir" "$tmp/keylo.tum" "$@" | awk '{print $4}')"
d="$(python3 "$root/scripts/bench/compare_poses.py" "$tmp/pcl.tum" "$tmp/keylo.tum")"
echo "$dir $* | $d | PCL ${p} ms keylo ${k} ms ratio $(awk -v a="$p" -v b="$k" 'BEGIN {printf "%.1f", a / b}')×"
