"""OpenCV contrib's FREAK, measured from its behaviour, written as the Rust tables of
crates/keylo-features/src/native/freak_opencv.rs (keylo's `freak` with `pattern = "opencv"`).

A model of OpenCV's FREAK sampling (the paper's retina pattern quantised to 64 scales x 256
orientations, receptive fields averaged over squares with edges rounded half to even from an
integral image, bilinear below half a pixel; orientation from 45 pairs with integer weights) gives the 43 field values
of a keypoint. With orientation off, each of the 512 descriptor bits is `v[i] >= v[j]` for one
of the 903 field pairs: the pair consistent with OpenCV's bits on 800 random keypoints is that
bit's. The full model (orientation on, sizes 3-200 px) is then checked against OpenCV's angles
and descriptors. The pattern is OpenCV contrib's (Apache-2.0, opencv_contrib xfeatures2d).

  python3 -m venv V && V/bin/pip install "opencv-contrib-python-headless<5" numpy
  V/bin/python scripts/peers/freak_pattern.py
"""
import math
import os
import sys

import cv2
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
OUT = os.path.join(ROOT, "crates/keylo-features/src/native/freak_opencv.rs")
NB_SCALES, NB_ORI, NB_POINTS, PATTERN_SCALE, N_OCTAVES = 64, 256, 43, 22.0, 4
RINGS = [6, 6, 6, 6, 6, 6, 6, 1]
BIG, SMALL = 2.0 / 3.0, 2.0 / 24.0
UNIT = (BIG - SMALL) / 21.0
RADIUS = [BIG, BIG - 6 * UNIT, BIG - 11 * UNIT, BIG - 15 * UNIT, BIG - 18 * UNIT, BIG - 20 * UNIT,
          SMALL, 0.0]
SIGMA = [RADIUS[0] / 2, RADIUS[1] / 2, RADIUS[2] / 2, RADIUS[3] / 2, RADIUS[4] / 2,
         RADIUS[5] / 2, RADIUS[6] / 2, RADIUS[6] / 2]
# The orientation pairs: on the four outer rings the three opposite pairs and the six pairs two
# fields apart, on the next three rings the opposite pairs (checked below against OpenCV).
ORIENTATION = []
for b in (0, 6, 12, 18):
    ORIENTATION += [(b, b + 3), (b + 1, b + 4), (b + 2, b + 5), (b, b + 2), (b + 1, b + 3),
                    (b + 2, b + 4), (b + 3, b + 5), (b + 4, b), (b + 5, b + 1)]
for b in (24, 30, 36):
    ORIENTATION += [(b, b + 3), (b + 1, b + 4), (b + 2, b + 5)]
SCALE_STEP = 2.0 ** (N_OCTAVES / NB_SCALES)
SIZE_CST = np.float32(NB_SCALES / (0.693147180559945 * N_OCTAVES))


def point(s, o, p):
    i, k = (p // 6, p % 6) if p < 42 else (7, 0)
    f = SCALE_STEP ** s
    theta = o * 2 * math.pi / NB_ORI
    beta = math.pi / RINGS[i] * (i % 2)
    alpha = k * 2 * math.pi / RINGS[i] + beta + theta
    return (np.float32(RADIUS[i] * math.cos(alpha) * f * PATTERN_SCALE),
            np.float32(RADIUS[i] * math.sin(alpha) * f * PATTERN_SCALE),
            np.float32(SIGMA[i] * f * PATTERN_SCALE))


SIZES = [max(int(math.ceil((RADIUS[i] + SIGMA[i]) * SCALE_STEP ** s * PATTERN_SCALE)) + 1
             for i in range(8)) for s in range(NB_SCALES)]


def mean(img, ii, kx, ky, s, o, p):
    x0, y0, r = point(s, o, p)
    xf, yf = np.float32(x0 + np.float32(kx)), np.float32(y0 + np.float32(ky))
    x, y = int(xf), int(yf)
    if r < 0.5:
        rx = int(np.float32(xf - np.float32(x)) * np.float32(1024))
        ry = int(np.float32(yf - np.float32(y)) * np.float32(1024))
        v = ((1024 - rx) * (1024 - ry) * int(img[y, x]) + rx * (1024 - ry) * int(img[y, x + 1])
             + (1024 - rx) * ry * int(img[y + 1, x]) + rx * ry * int(img[y + 1, x + 1]))
        return (v + 2 * 1024 * 1024) // (4 * 1024 * 1024)
    # The square's edges rounded half to even (cvRound); the integral image is 1 px larger.
    one = np.float32(1)
    xl, yt = int(np.rint(np.float32(xf - r))), int(np.rint(np.float32(yf - r)))
    xr, yb = int(np.rint(np.float32(xf + r + one))), int(np.rint(np.float32(yf + r + one)))
    v = int(ii[yb, xr]) - int(ii[yb, xl]) + int(ii[yt, xl]) - int(ii[yt, xr])
    area = (xr - xl) * (yb - yt)
    return (v + area // 2) // area


def weights():
    out = []
    for i, j in ORIENTATION:
        (xi, yi, _), (xj, yj, _) = point(0, 0, i), point(0, 0, j)
        dx, dy = np.float32(xi - xj), np.float32(yi - yj)
        n2 = np.float32(dx * dx + dy * dy)
        out.append((math.floor(float(np.float32(dx / n2)) * 4096.0 + 0.5),
                    math.floor(float(np.float32(dy / n2)) * 4096.0 + 0.5)))
    return out


def measure_pairs(rng):
    ext = cv2.xfeatures2d.FREAK_create(orientationNormalized=False)
    values, bits = [], []
    for _ in range(40):
        img = cv2.GaussianBlur(rng.integers(0, 256, (160, 240)).astype(np.uint8), (0, 0),
                               rng.uniform(1, 4))
        ii = cv2.integral(img, sdepth=cv2.CV_32S)
        kps = [cv2.KeyPoint(float(x), float(y), 7.0) for x, y in rng.uniform(40, 120, (20, 2))]
        kps, d = ext.compute(img, kps)
        for k, row in zip(kps, d):
            values.append([mean(img, ii, k.pt[0], k.pt[1], 0, 0, p) for p in range(NB_POINTS)])
            bits.append(np.unpackbits(row))
    V, B = np.array(values), np.array(bits)
    pairs = []
    for b in range(512):
        found = [(i, j) for i in range(1, NB_POINTS) for j in range(i)
                 if np.array_equal((V[:, i] >= V[:, j]).astype(np.uint8), B[:, b])]
        if len(found) != 1:
            sys.exit(f"bit {b}: {len(found)} consistent pairs")
        pairs.append(found[0])
    return pairs


def describe(img, ii, kp, pairs, w):
    s = min(max(int(float(np.float32(np.float32(math.log(kp.size / 7.0)) * SIZE_CST)) + 0.5), 0),
            NB_SCALES - 1)
    x, y = kp.pt
    if x <= SIZES[s] or y <= SIZES[s] or x >= img.shape[1] - SIZES[s] or y >= img.shape[0] - SIZES[s]:
        return None
    v = [mean(img, ii, x, y, s, 0, p) for p in range(NB_POINTS)]
    d0 = d1 = 0
    for (i, j), (wx, wy) in zip(ORIENTATION, w):
        delta = v[i] - v[j]
        d0 += int(delta * wx / 2048)
        d1 += int(delta * wy / 2048)
    angle = np.float32(float(np.arctan2(np.float32(d1), np.float32(d0))) * (180.0 / math.pi))
    t = float(np.float32(NB_ORI) * angle) * (1 / 360.0)
    t = int(t - 0.5) if angle < 0 else int(t + 0.5)
    t = t + NB_ORI if t < 0 else (t - NB_ORI if t >= NB_ORI else t)
    v = [mean(img, ii, x, y, s, t, p) for p in range(NB_POINTS)]
    return angle, np.packbits(np.array([v[i] >= v[j] for i, j in pairs], np.uint8))


def check(rng, pairs):
    ext, w = cv2.xfeatures2d.FREAK_create(), weights()
    for _ in range(20):
        img = cv2.GaussianBlur(rng.integers(0, 256, (400, 600)).astype(np.uint8), (0, 0),
                               rng.uniform(1, 4))
        ii = cv2.integral(img, sdepth=cv2.CV_32S)
        # Half the keypoints at whole pixels (as FAST's): edges then fall on half pixels.
        xs, ys = rng.uniform(0, 600, 60), rng.uniform(0, 400, 60)
        xs[::2], ys[::2] = np.round(xs[::2]), np.round(ys[::2])
        kps = [cv2.KeyPoint(float(x), float(y), float(sz), -1, 0, 0, i) for i, (x, y, sz) in
               enumerate(zip(xs, ys, rng.uniform(3, 200, 60)))]
        mine = {k.class_id: describe(img, ii, k, pairs, w) for k in kps}
        kept, d = ext.compute(img, kps)
        if {k.class_id for k in kept} != {c for c, m in mine.items() if m is not None}:
            sys.exit("the model keeps other keypoints than OpenCV")
        for k, row in zip(kept, d):
            angle, bits = mine[k.class_id]
            if abs(angle - k.angle) > 1e-4 or not np.array_equal(bits, row):
                sys.exit(f"the model differs from OpenCV at size {k.size}")


def main():
    rng = np.random.default_rng(3)
    pairs = measure_pairs(rng)
    check(rng, pairs)
    rows = "\n".join(f"    [{i}, {j}]," for i, j in pairs)
    ori = "\n".join(f"    [{i}, {j}]," for i, j in ORIENTATION)
    with open(OUT, "w") as f:
        f.write(f"""//! OpenCV contrib's FREAK tables (`cv::xfeatures2d::FREAK`, opencv_contrib, Apache-2.0), as
//! measured from its behaviour by `scripts/peers/freak_pattern.py` (OpenCV {cv2.__version__});
//! generated, do not edit.
//!
//! Fields are numbered ring by ring from the outside (0–5 the outer ring, 42 the centre).

/// The descriptor's 512 tests `[i, j]`, in the order of the descriptor's bits (most
/// significant bit of each byte first): bit set when field i is at least as bright as field j.
pub const PAIRS: [[u8; 2]; 512] = [
{rows}
];

/// The 45 orientation pairs `[i, j]`: field i minus field j, along the vector from j to i.
pub const ORIENTATION_PAIRS: [[u8; 2]; 45] = [
{ori}
];
""")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
