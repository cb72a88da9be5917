#!/usr/bin/env bash
# The same-budget study on real KITTI scans (docs/results/odometry.md): one
# `keylo compare --same-budget` per drive over the raw cloud and the paper's outdoor AKAZE and
# SuperPoint keypoint clouds with KISS-ICP, NDT and (AKAZE) hybrid; the keypoint configs also
# run with a `random` and a `voxel-budget` sample of the same per-frame point count.
#   bash scripts/study/same_budget_kitti.sh SFND_SCANS UPSTREAM_POSES [OUT]
# SFND_SCANS: the 78 KITTI raw scans of udacity/SFND_3D_Object_Tracking
# (images/KITTI/2011_09_26/velodyne_points/data/; read from a local copy, never committed);
# UPSTREAM_POSES: official KISS-ICP's poses on them, KITTI format
# (../shared/peers/kiss_icp_reference.sh SFND_SCANS DIR → DIR/kiss_icp_poses_kitti.txt), the
# reference there (that drive has no ground truth). The two 10-scan snippets of
# ../shared/data/kitti_mini run against their SemanticKITTI poses.
set -euo pipefail
cd "$(dirname "$0")/../.."
keylo=${KEYLO:-target/release/keylo}
scans=$1
upstream=$2
out=${3:-/tmp/study-kitti}
mkdir -p "$out"
P=configs/paper
configs=("$P/raw-kiss-icp.toml" "$P/raw-ndt.toml"
         "$P/outdoor-akaze-kiss-icp.toml" "$P/outdoor-superpoint-kiss-icp.toml"
         "$P/outdoor-akaze-ndt.toml" "$P/outdoor-superpoint-ndt.toml" "$P/outdoor-akaze-hybrid.toml")
run() {
    local name=$1 data=$2 gt=$3 start
    start=$(date +%s)
    "$keylo" -q compare "${configs[@]}" --data "$data" --gt "$gt" --same-budget --timeout 600 --out "$out/cmp-$name"
    echo "$name: $(( $(date +%s) - start )) s -> $out/cmp-$name/compare.md"
}
run sfnd78 "$scans" "$upstream"
for s in 00 01; do
    run "kitti$s" "../shared/data/kitti_mini/$s" "../shared/data/kitti_mini/$s/poses_semantickitti_velo.txt"
done
