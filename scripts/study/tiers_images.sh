#!/usr/bin/env bash
# All 1146 signal images of the paper's study (TIERS indoor_01_square, OS0-128; MIT, from the
# authors' repository), for measuring `keylo sim realism` on stretches that ../shared does not
# hold: ../shared/data/tiers_signal has images 0–599; the sensor stands still again over the
# recording's last ~150 (about 1000–1145), the still images the `ouster` lab was not tuned on.
# Needs the network; the images are for measuring only and never enter the repository.
#
#   scripts/study/tiers_images.sh DEST
#   keylo sim realism --real DEST --real-start 1046 --real-frames 99 --moving-start 300 …
set -euo pipefail
dest="${1:?usage: scripts/study/tiers_images.sh DEST}"
repo="${TIERS_REPO:-https://github.com/TIERS/ws-lidar-as-camera-odom.git}"  # or a local git dir
commit="c15cd31598ffdbc44aecfd18293f4915e1156d81"   # as ../shared/data/tiers_signal/PROVENANCE.md
folder="detector_descriptor_for_LiDARimg/Dataset/signal_image"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
if git --git-dir "$repo" rev-parse -q --verify "$commit^{commit}" >/dev/null 2>&1; then
  gitdir="$repo"                       # a local clone or mirror that has the commit
else
  git clone -q --bare --filter=blob:none "$repo" "$tmp/repo.git"
  gitdir="$tmp/repo.git"
fi
mkdir -p "$dest"
for f in $(git --git-dir "$gitdir" ls-tree --name-only "$commit" "$folder/" | grep '/image_[0-9]*\.png$'); do
  git --git-dir "$gitdir" show "$commit:$f" > "$dest/$(basename "$f")"
done
n="$(ls "$dest"/image_*.png | wc -l)"
echo "$n images in $dest" >&2
[ "$n" -eq 1146 ] || { echo "expected 1146 images" >&2; exit 1; }
