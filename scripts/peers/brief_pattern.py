"""OpenCV contrib's BRIEF test pattern, measured from its behaviour, written as the Rust table
crates/keylo-features/src/native/brief_opencv.rs (keylo's `brief` with `pattern = "opencv"`).

BRIEF bit k of a keypoint is `S(a_k) < S(b_k)`, S a 9x9 box sum at an offset from the
keypoint. On a black image with one white pixel only the bits whose b-box holds it and whose
a-box does not are set; on a white image with one black pixel, those whose a-box holds it.
Moving the pixel over the 57x57 offsets around a keypoint gives each box minus the other, so
both offsets, for the 512 tests of the 64-byte descriptor (the 16- and 32-byte ones are its
prefixes: checked here). The table is then checked against OpenCV's descriptors on random
images. The pattern is OpenCV contrib's (Apache-2.0, opencv_contrib modules/xfeatures2d).

  python3 -m venv V && V/bin/pip install "opencv-contrib-python-headless<5" numpy
  V/bin/python scripts/peers/brief_pattern.py
"""
import os
import sys

import cv2
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
OUT = os.path.join(ROOT, "crates/keylo-features/src/native/brief_opencv.rs")
N, C, REACH, HALF = 120, 60, 28, 4


def bits(img, nbytes):
    ext = cv2.xfeatures2d.BriefDescriptorExtractor_create(nbytes, False)
    _, d = ext.compute(img, [cv2.KeyPoint(float(C), float(C), 7.0)])
    return np.unpackbits(d[0])


def box(cx, cy):
    return {(cx + i, cy + j) for i in range(-HALF, HALF + 1) for j in range(-HALF, HALF + 1)}


def pattern(nbytes):
    nbits = nbytes * 8
    only_b = [set() for _ in range(nbits)]
    only_a = [set() for _ in range(nbits)]
    for dy in range(-REACH, REACH + 1):
        for dx in range(-REACH, REACH + 1):
            img = np.zeros((N, N), np.uint8)
            img[C + dy, C + dx] = 255
            for k in np.nonzero(bits(img, nbytes))[0]:
                only_b[k].add((dx, dy))
            img = np.full((N, N), 255, np.uint8)
            img[C + dy, C + dx] = 0
            for k in np.nonzero(bits(img, nbytes))[0]:
                only_a[k].add((dx, dy))
    pairs = []
    for k in range(nbits):
        a_only, b_only = only_a[k], only_b[k]
        if not a_only and not b_only:
            sys.exit(f"test {k}: both boxes the same; cannot be measured")

        def centres(pts):
            xs, ys = [p[0] for p in pts], [p[1] for p in pts]
            return [(x, y) for x in range(max(xs) - HALF, min(xs) + HALF + 1)
                    for y in range(max(ys) - HALF, min(ys) + HALF + 1)]

        found = [(a, b) for a in centres(a_only) for b in centres(b_only)
                 if box(*a) - box(*b) == a_only and box(*b) - box(*a) == b_only]
        if len(found) != 1:
            sys.exit(f"test {k}: {len(found)} candidate pairs")
        pairs.append(found[0])
    return pairs


def check(pairs):
    rng = np.random.default_rng(1)
    img = cv2.GaussianBlur(rng.integers(0, 256, (200, 300)).astype(np.uint8), (5, 5), 2)
    s = cv2.integral(img, sdepth=cv2.CV_32S)

    def S(x, y):
        return int(s[y + 5, x + 5] - s[y + 5, x - 4] - s[y - 4, x + 5] + s[y - 4, x - 4])

    for nbytes in (16, 32, 64):
        ext = cv2.xfeatures2d.BriefDescriptorExtractor_create(nbytes, False)
        kps = [cv2.KeyPoint(float(x), float(y), 7) for x, y in rng.uniform(30, 170, (300, 2))]
        kps, d = ext.compute(img, kps)
        for k, row in zip(kps, d):
            x, y = int(k.pt[0] + 0.5), int(k.pt[1] + 0.5)
            b = [S(x + a[0], y + a[1]) < S(x + c[0], y + c[1]) for a, c in pairs[:nbytes * 8]]
            if not np.array_equal(np.packbits(np.array(b, np.uint8)), row):
                sys.exit(f"{nbytes} bytes: the measured pattern does not reproduce OpenCV")


def main():
    full = pattern(64)
    for nbytes in (16, 32):
        if pattern(nbytes) != full[:nbytes * 8]:
            sys.exit(f"the {nbytes}-byte pattern is not a prefix of the 64-byte one")
    check(full)
    rows = "\n".join(f"    [{a[0]}, {a[1]}, {b[0]}, {b[1]}]," for a, b in full)
    with open(OUT, "w") as f:
        f.write(f"""//! OpenCV contrib's BRIEF test pattern (`cv::xfeatures2d::BriefDescriptorExtractor`,
//! opencv_contrib, Apache-2.0), as measured from its behaviour by
//! `scripts/peers/brief_pattern.py` (OpenCV {cv2.__version__}); generated, do not edit.
//!
//! Test k compares the 9×9 box sums at `(ax, ay)` and `(bx, by)` (pixels from the keypoint,
//! x right, y down): bit k is `S(a) < S(b)`, most significant bit of each byte first. The 16-
//! and 32-byte descriptors use the first 128 and 256 tests.

/// `[ax, ay, bx, by]` per test.
pub const PAIRS: [[i8; 4]; 512] = [
{rows}
];
""")
    print(f"wrote {OUT}: {len(full)} tests")


if __name__ == "__main__":
    main()
