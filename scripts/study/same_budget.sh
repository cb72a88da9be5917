#!/usr/bin/env bash
# The same-budget study (docs/results/odometry.md): four simulated scenes with the `ouster`
# appearance, 300 frames each, and one `keylo compare --same-budget` per scene over the raw
# cloud and the paper's AKAZE and SuperPoint keypoint clouds with KISS-ICP, NDT and (AKAZE)
# hybrid and GICP; every keypoint config also runs with a `random` and a `voxel-budget` sample of the
# same per-frame point count.
#   bash scripts/study/same_budget.sh [OUT]        # OUT defaults to /tmp/study; ~30 min on 2 cores
#   SCENES=lab bash scripts/study/same_budget.sh   # some of the scenes only
set -euo pipefail
cd "$(dirname "$0")/../.."
keylo=${KEYLO:-target/release/keylo}
out=${1:-/tmp/study}
frames=${FRAMES:-300}
mkdir -p "$out"
P=configs/paper
for scene in ${SCENES:-lab corridor road park}; do
    data="$out/$scene-ouster"
    [ -f "$data/gt.tum" ] || "$keylo" -q sim --scene "$scene" --frames "$frames" --set appearance=ouster --out "$data"
    case $scene in lab|corridor) io=indoor ;; *) io=outdoor ;; esac
    configs=("$P/raw-kiss-icp.toml" "$P/raw-ndt.toml" "$P/raw-gicp.toml"
             "$P/$io-akaze-kiss-icp.toml" "$P/$io-superpoint-kiss-icp.toml"
             "$P/$io-akaze-ndt.toml" "$P/$io-superpoint-ndt.toml" "$P/$io-akaze-hybrid.toml"
             "$P/$io-akaze-gicp.toml")
    start=$(date +%s)
    "$keylo" -q compare "${configs[@]}" --data "$data" --same-budget --timeout 600 --out "$out/cmp-$scene"
    echo "$scene: $(( $(date +%s) - start )) s -> $out/cmp-$scene/compare.md"
done
