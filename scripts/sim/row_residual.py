"""Row-to-row and column-to-column structure of 8-bit signal images: the median and 90th
percentile of |pixel − mean of the pixels above and below| (row residual) and of
|pixel − mean of the pixels left and right| (column residual), per band of rows, at full
size and resized to 1024×64 (linear) as the keypoint study sees them.

    /usr/bin/python3 scripts/sim/row_residual.py ../shared/data/tiers_signal
    # simulated: a keylo frame folder, its signal made 8-bit as the real images were (Ouster's
    # ROS driver: auto exposure and square root; driver_image.py)
    keylo sim --scene lab --frames 24 --set appearance=ouster --set columns=2048 \
        --set speed_scale=0 --set sway_scale=0 --out /tmp/lab-still
    /usr/bin/python3 scripts/sim/row_residual.py /tmp/lab-still

keylo-sim's `ouster` appearance was checked with it (docs/results/sim-realism.md). Needs
numpy and OpenCV-Python (Debian: python3-opencv).
"""

import glob
import os
import struct
import sys

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from driver_image import driver_image  # noqa: E402

IMAGES = 24
BANDS = 8


def klf_signal(path):
    """The signal of a keylo frame file (docs/formats.md) as the driver's 8-bit image."""
    data = open(path, "rb").read()
    if data[:4] != b"KLF1":
        sys.exit(f"{path}: not a keylo frame file (no KLF1 magic)")
    rows, cols = struct.unpack("<II", data[4:12])
    n = rows * cols
    start = 28 + 8 * cols + 4 * n
    counts = np.frombuffer(data, "<f4", n, start).reshape(rows, cols)
    return driver_image(counts.astype(np.float64))


def images(path):
    if os.path.exists(os.path.join(path, "keylo-frames.json")):
        files = sorted(glob.glob(path + "/frames/*.klf"))[:IMAGES]
        return [klf_signal(f) for f in files]
    files = sorted(glob.glob(path + "/*.png"))[:IMAGES]
    return [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files]


def residuals(im):
    im = im.astype(float)
    row = np.abs(im[1:-1] - (im[:-2] + im[2:]) / 2)
    col = np.abs(im[:, 1:-1] - (im[:, :-2] + im[:, 2:]) / 2)
    return row, col[1:-1]


def main():
    frames = images(sys.argv[1])
    if not frames:
        sys.exit(f"{sys.argv[1]}: no PNG images and no keylo frames")
    whole = np.mean([[np.median(r) for r in residuals(im)] for im in frames], axis=0)
    print(f"whole images, full size: median row residual {whole[0]:.1f},"
          f" median column residual {whole[1]:.1f}")
    for name, size in (("full size", None), ("1024x64", (1024, 64))):
        per_band = [[] for _ in range(BANDS)]
        for im in frames:
            if size:
                im = cv2.resize(im, size, interpolation=cv2.INTER_LINEAR)
            row, col = residuals(im)
            h = row.shape[0]
            for b in range(BANDS):
                sl = slice(b * h // BANDS, (b + 1) * h // BANDS)
                per_band[b].append([np.median(row[sl]), np.percentile(row[sl], 90),
                                    np.median(col[sl]), np.percentile(col[sl], 90)])
        print(f"{name}: {len(frames)} images; per eighth of the rows, top first:"
              " row residual p50/p90, column residual p50/p90")
        for b, v in enumerate(per_band):
            m = np.mean(v, axis=0)
            print(f"  rows {b + 1}/{BANDS}: {m[0]:5.1f} / {m[1]:5.1f}    {m[2]:5.1f} / {m[3]:5.1f}")


if __name__ == "__main__":
    main()
