"""Where in the image the keypoints are: per detector, the mean number of keypoints in each
eighth of the rows (top first) of 1024x64 images, real against simulated.

Counts alone can agree while the corners sit elsewhere (on the floor instead of the upper
walls), and that matters for odometry: a keypoint cloud's geometry is where its keypoints are.

    /usr/bin/python3 scripts/sim/keypoint_rows.py ../shared/data/tiers_signal /tmp/lab-still*

The first folder holds the real 8-bit images (PNG; the first 100 are used), the others keylo
frame folders (`keylo sim ... --out DIR`) whose signal is made 8-bit as Ouster's ROS driver
makes it (driver_image.py), or PNG folders. The detectors are the keypoint study's, as
scripts/peers/kpeval_reference.py makes them. Prints a markdown table and, per detector, the share of keypoints
that would have to move between eighths for the simulated profile to become the real one.
Needs numpy and OpenCV-Python.
"""

import glob
import os
import sys

import cv2
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "peers"))
from kpeval_reference import H, W, detector  # noqa: E402
from row_residual import klf_signal  # noqa: E402

REAL_IMAGES = 100
BANDS = 8
SIZE = (W, H)
DETECTORS = ["AKAZE", "ORB", "FAST", "SHITOMASI", "HARRIS", "SIFT", "BRISK"]


def load(folder, limit=None):
    """The folder's 8-bit images, resized as the keypoint study resizes them."""
    if os.path.exists(os.path.join(folder, "keylo-frames.json")):
        images = [klf_signal(f) for f in sorted(glob.glob(folder + "/frames/*.klf"))]
    else:
        files = sorted(glob.glob(folder + "/*.png"))[:limit]
        images = [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files]
    if not images:
        sys.exit(f"{folder}: no keylo frames and no PNG images")
    return [cv2.resize(im, SIZE, interpolation=cv2.INTER_LINEAR) for im in images]


def profile(images, detector):
    """Mean keypoints per eighth of the rows, and the median count."""
    per_image = []
    for im in images:
        rows = [kp.pt[1] for kp in detector.detect(im)]
        per_image.append(np.histogram(rows, bins=BANDS, range=(0, SIZE[1]))[0])
    per_image = np.array(per_image)
    return per_image.mean(axis=0), float(np.median(per_image.sum(axis=1)))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    real = load(sys.argv[1], REAL_IMAGES)
    sim = [im for folder in sys.argv[2:] for im in load(folder)]
    print(f"real: {len(real)} images; simulated: {len(sim)} images\n")
    print("| detector | images | median count | keypoints per eighth of the rows, top first | to move |")
    print("|---|---|---|---|---|")
    for name in DETECTORS:
        det = detector(name)
        r, rc = profile(real, det)
        s, sc = profile(sim, det)
        # Half the L1 distance of the two normalised profiles.
        moved = 0.5 * np.abs(r / max(r.sum(), 1e-9) - s / max(s.sum(), 1e-9)).sum()
        print(f"| {name} | real | {rc:.0f} | {' '.join(f'{v:.0f}' for v in r)} | |")
        print(f"| {name} | sim | {sc:.0f} | {' '.join(f'{v:.0f}' for v in s)} | {moved:.0%} |")


if __name__ == "__main__":
    main()
