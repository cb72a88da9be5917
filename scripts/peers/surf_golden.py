"""Golden SURF keypoints and descriptors from OpenCV's own SURF (opencv-contrib 3.4.2, the last
PyPI wheel with the non-free xfeatures2d; it reproduces the paper's SURF counts), for
keylo's `surf` (crates/keylo-features/tests/surf.rs). Default SURF: hessianThreshold 100,
4 octaves, 3 layers, 64-d, not upright. Images resized to 1024x64 with linear interpolation,
as the paper.

Writes tests/fixtures/surf/golden.json:
  images: per committed image (tests/fixtures/kpeval/images/{os0,sim}/*.png): the resized
          image's SHA-256, every keypoint [x, y, size, angle, response, octave, class_id] in
          OpenCV's order, and the descriptors of the first DESCRIBED keypoints; the same for
          SURF describing FAST's keypoints (threshold 30, the paper's), as `fast_surf`, on
          each set's first image; floats as their shortest float32 decimals;
  tiers_counts: keypoints per image of ../shared/data/tiers_signal/image_0000..0599.png
          (where present).

  python3.7 -m venv V && V/bin/pip install "opencv-contrib-python==3.4.2.17" "numpy<1.22"
  V/bin/python scripts/peers/surf_golden.py
"""
import glob
import hashlib
import json
import os
import sys

import cv2
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DESCRIBED = 30


def load(path):
    img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if img is None:
        sys.exit("cannot read " + path)
    return cv2.resize(img, (1024, 64), interpolation=cv2.INTER_LINEAR)


def f32(v):
    """A float32 written as its shortest round-trip decimal (read back as f32 exactly)."""
    return float(repr(np.float32(v)))


def rows(kps):
    return [[f32(k.pt[0]), f32(k.pt[1]), f32(k.size), f32(k.angle), f32(k.response), k.octave,
             k.class_id] for k in kps]


def desc_rows(desc):
    return [[f32(v) for v in row] for row in desc[:DESCRIBED]]


def main():
    assert cv2.__version__.startswith("3.4.2"), cv2.__version__
    surf = cv2.xfeatures2d.SURF_create()
    assert (surf.getHessianThreshold(), surf.getNOctaves(), surf.getNOctaveLayers(),
            surf.getExtended(), surf.getUpright()) == (100.0, 4, 3, False, False)
    out = {"opencv": cv2.__version__, "size": [1024, 64], "described": DESCRIBED, "images": {},
           "tiers_counts": []}
    for path in sorted(glob.glob(os.path.join(ROOT, "tests/fixtures/kpeval/images/*/*.png"))):
        img = load(path)
        kps, desc = surf.detectAndCompute(img, None)
        name = os.path.relpath(path, ROOT)
        fast_kps = cv2.FastFeatureDetector_create(threshold=30).detect(img, None)
        fast_kps, fast_desc = surf.compute(img, fast_kps)
        out["images"][name] = {
            "sha256": hashlib.sha256(img.tobytes()).hexdigest(),
            "keypoints": rows(kps),
            "descriptors": desc_rows(desc),
        }
        if name.endswith("frame000000_signal.png"):
            out["images"][name]["fast_surf"] = {"keypoints": rows(fast_kps),
                                                "descriptors": desc_rows(fast_desc)}
        print(name, len(kps), file=sys.stderr)
    tiers = os.path.join(ROOT, "..", "shared", "data", "tiers_signal")
    if os.path.isdir(tiers):
        for i in range(600):
            kps = surf.detect(load(os.path.join(tiers, "image_%04d.png" % i)), None)
            out["tiers_counts"].append(len(kps))
    with open(os.path.join(ROOT, "tests/fixtures/surf/golden.json"), "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
