"""Per-beam signal gains of a real Ouster from its 8-bit signal images: for every row, the
median over images and columns of the pixel over the mean of the rows 1 and 2 above and
below (pixels 10..250 only, so dark and saturated ones do not count), normalised to mean 1.
The first and last two rows, which lack neighbours, repeat the four-beam pattern of the rest.

    /usr/bin/python3 scripts/sim/beam_gains.py ../shared/data/tiers_signal

Prints the table keylo-sim's `ouster` appearance uses (crates/keylo-sim/src/appearance.rs).
Needs numpy and OpenCV-Python (Debian: python3-opencv).
"""

import glob
import sys

import cv2
import numpy as np


def main():
    files = sorted(glob.glob(sys.argv[1] + "/*.png"))
    ratios = []
    for f in files:
        im = cv2.imread(f, cv2.IMREAD_GRAYSCALE).astype(float)
        m = np.where((im > 10) & (im < 250), im, np.nan)
        nb = (np.roll(m, 1, 0) + np.roll(m, -1, 0) + np.roll(m, 2, 0) + np.roll(m, -2, 0)) / 4
        ratios.append(np.nanmedian(m / nb, axis=1))
    r = np.nanmedian(np.array(ratios), axis=0)
    rows = len(r)
    inner = r[2:rows - 2]
    phase = [np.nanmedian(inner[(k - 2) % 4::4]) for k in range(4)]
    for k in (0, 1, rows - 2, rows - 1):
        r[k] = phase[k % 4]
    r = r / r.mean()
    print(f"// {len(files)} images of {sys.argv[1]}")
    for i in range(0, rows, 8):
        print("    " + " ".join(f"{v:.3f}," for v in r[i:i + 8]))


if __name__ == "__main__":
    main()
