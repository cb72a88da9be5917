"""OpenCV contrib's BRIEF (and FREAK) descriptors on the committed real and simulated images,
for keylo's `brief` and `freak` (crates/keylo-features/tests/brief_freak_opencv.rs).

Images: tests/fixtures/kpeval/images/{os0,sim}/*.png resized to 1024x64 (linear), as the
paper. Keypoints: FAST (threshold 30, the paper's) and ORB's (with angles, for the oriented
variants), kept in the fixture so both sides describe the very same keypoints. Per image,
keypoint set and descriptor: the keypoints (x, y, size, angle, response, octave, class_id),
the indices OpenCV kept, and the descriptors as hex rows.

  python3 -m venv V && V/bin/pip install "opencv-contrib-python-headless<5" numpy
  V/bin/python scripts/peers/brief_freak_golden.py
"""
import glob
import json
import os

import cv2
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
OUT = os.path.join(ROOT, "tests/fixtures/brief_freak/golden.json")
EXTRACTORS = {
    "brief": lambda: cv2.xfeatures2d.BriefDescriptorExtractor_create(32, False),
    "brief_oriented": lambda: cv2.xfeatures2d.BriefDescriptorExtractor_create(32, True),
    "freak": cv2.xfeatures2d.FREAK_create,
}


def f32(v):
    return float(str(np.float32(v)))


def row(k):
    return [f32(k.pt[0]), f32(k.pt[1]), f32(k.size), f32(k.angle), f32(k.response), k.octave,
            k.class_id]


def main():
    out = {"opencv": cv2.__version__, "images": {}}
    for path in sorted(glob.glob(os.path.join(ROOT, "tests/fixtures/kpeval/images/*/*.png"))):
        img = cv2.resize(cv2.imread(path, cv2.IMREAD_GRAYSCALE), (1024, 64),
                         interpolation=cv2.INTER_LINEAR)
        sets = {
            "fast": cv2.FastFeatureDetector_create(threshold=30).detect(img, None),
            "orb": cv2.ORB_create().detect(img, None),
        }
        entry = {}
        for set_name, kps in sets.items():
            entry[set_name] = {"keypoints": [row(k) for k in kps]}
            for ext_name, make in EXTRACTORS.items():
                # Tag each keypoint with its index (class_id) to see which ones OpenCV kept.
                tagged = [cv2.KeyPoint(k.pt[0], k.pt[1], k.size, k.angle, k.response, k.octave, i)
                          for i, k in enumerate(kps)]
                kept, desc = make().compute(img, tagged)
                entry[set_name][ext_name] = {
                    "kept": [k.class_id for k in kept],
                    "descriptors": [bytes(r).hex() for r in (desc if desc is not None else [])],
                }
        out["images"][os.path.relpath(path, ROOT)] = entry
    with open(OUT, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")
    print("wrote", OUT)


if __name__ == "__main__":
    main()
