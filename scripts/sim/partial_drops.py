"""Partial drops in still signal images: pixels that read far below their usual signal.

Each pixel of a stack of still 8-bit images (a real still sensor, or `keylo sim` held still) is
compared with its median over the stack. Prints, per median grey level and per eighth of the
rows, the share of pixels below half their median; how long such drops run along a row; and
what share of its median a dropped pixel reads.

    /usr/bin/python3 scripts/sim/partial_drops.py ../shared/data/tiers_signal
    keylo sim --scene lab --frames 40 --set appearance=ouster --set columns=2048 \
        --set speed_scale=0 --set sway_scale=0 --out /tmp/lab-still
    /usr/bin/python3 scripts/sim/partial_drops.py /tmp/lab-still

With a pcap (needs the keylo Python package), consecutive frames are compared instead: the
share of pixel pairs whose signals differ by more than a factor of two.

    python scripts/sim/partial_drops.py ../shared/data/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap

keylo-sim's `ouster` partial drops were measured with it (docs/results/sim-realism.md). Needs
numpy and OpenCV-Python.
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import row_residual  # noqa: E402

STACK = 40
BINS = [(40, 80), (80, 120), (120, 160), (160, 256)]


def stack_report(stack):
    med = np.median(stack, axis=0)
    ratio = stack / np.maximum(med, 1)
    low = ratio < 0.5
    print(f"{len(stack)} images; share of pixels below half their median, by median grey level:")
    print("  " + "  ".join(f"[{a},{b}): {low[:, (med >= a) & (med < b)].mean() * 100:.2f} %" for a, b in BINS))
    rows = stack.shape[1]
    print("per eighth of the rows (top first), pixels of median grey >= 80:")
    shares = []
    for k in range(8):
        band = slice(k * rows // 8, (k + 1) * rows // 8)
        sel = med[band] >= 80
        shares.append(low[:, band][:, sel].mean() * 100 if sel.any() else float("nan"))
    print("  " + " ".join(f"{s:.2f}" for s in shares) + " %")
    runs = []
    for image in low:
        for line in image.astype(int):
            edges = np.diff(np.concatenate([[0], line, [0]]))
            runs += list(np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1))
    runs = np.array(runs)
    if runs.size:
        print("runs along a row: " + ", ".join(f"{k} px {np.mean(runs == k) * 100:.0f} %" for k in (1, 2, 3))
              + f", longer {np.mean(runs > 3) * 100:.0f} %")
        sel = low & (med >= 80)
        q = np.percentile(ratio[sel], [10, 50, 90])
        print(f"a dropped pixel (median grey >= 80) reads {q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} of its median (10th / 50th / 90th percentile)")


def pcap_report(path):
    import keylo

    frames = list(keylo.open(path, partial_frames="skip-ends"))
    pairs = kept = 0
    for a, b in zip(frames, frames[1:]):
        sa, sb = a.signal.astype(float), b.signal.astype(float)
        both = a.valid & b.valid
        hi = np.maximum(sa, sb)
        sel = both & (hi > np.percentile(hi[both], 30))
        pairs += int(sel.sum())
        kept += int((np.minimum(sa, sb)[sel] < 0.5 * hi[sel]).sum())
    print(f"{len(frames)} complete frames; {kept} of {pairs} pixel pairs of consecutive frames "
          "(the brighter 70 %) differ by more than a factor of two")


def main():
    path = sys.argv[1]
    if path.endswith(".pcap"):
        pcap_report(path)
        return
    row_residual.IMAGES = STACK
    images = row_residual.images(path)
    if len(images) < 5:
        sys.exit(f"{path}: need at least 5 still images, found {len(images)}")
    stack_report(np.stack([im.astype(float) for im in images]))


if __name__ == "__main__":
    main()
