"""Is the frame-to-frame noise of still signal images correlated between neighbouring pixels?

Each pixel of a stack of still 8-bit images is compared with its median over the stack; the
correlation of those deviations between a pixel and the pixel k columns to its right (k = 1, 2,
4, 8, 16) and k rows below (k = 1, 2, 4) is printed, over pixels of median grey >= 40 whose
deviations are under 40 grey levels (partial drops left out), with the robust sigma.

    python scripts/sim/noise_correlation.py ../shared/data/tiers_signal
    keylo sim --scene lab --frames 24 --set appearance=ouster --set columns=2048 \
        --set speed_scale=0 --set sway_scale=0 --out /tmp/lab-still
    python scripts/sim/noise_correlation.py /tmp/lab-still

Needs numpy and OpenCV-Python (as row_residual.py, whose image reader it uses).
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import row_residual  # noqa: E402


def main():
    stack = np.array(row_residual.images(sys.argv[1]), dtype=float)
    median = np.median(stack, axis=0)
    dev = stack - median
    ok = (median >= 40)[None] & (np.abs(dev) < 40)

    def corr(rows, cols):
        h, w = median.shape
        a, b = dev[:, : h - rows, : w - cols], dev[:, rows:, cols:]
        both = ok[:, : h - rows, : w - cols] & ok[:, rows:, cols:]
        return np.corrcoef(a[both], b[both])[0, 1]

    print(f"{sys.argv[1]}: {len(stack)} images {stack.shape[2]}x{stack.shape[1]}, "
          f"robust sigma {1.4826 * np.median(np.abs(dev[ok])):.2f} grey levels")
    print("  along a row, lags 1 2 4 8 16:", " ".join(f"{corr(0, k):.3f}" for k in (1, 2, 4, 8, 16)))
    print("  along a column, lags 1 2 4:  ", " ".join(f"{corr(k, 0):.3f}" for k in (1, 2, 4)))


if __name__ == "__main__":
    main()
