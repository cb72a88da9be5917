"""OpenCV contrib's BRIEF and FREAK on real images, for scripts/bench/brief_freak_vs_opencv.sh:
per image (8-bit grey PNGs image_0000.png..., resized to 1024x64 linear), FAST (threshold 30)
and BRISK keypoints, the indices each descriptor kept and a SHA-256 prefix of each row.

Usage: python3 brief_freak_opencv_dump.py IMAGE_DIR COUNT OUT.json
"""
import hashlib
import json
import os
import sys

import cv2
import numpy as np

image_dir, count, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
extractors = {"brief": lambda: cv2.xfeatures2d.BriefDescriptorExtractor_create(32, False),
              "freak": cv2.xfeatures2d.FREAK_create}
result = {"opencv": cv2.__version__, "images": []}
for i in range(count):
    img = cv2.resize(cv2.imread(os.path.join(image_dir, "image_%04d.png" % i), cv2.IMREAD_GRAYSCALE),
                     (1024, 64), interpolation=cv2.INTER_LINEAR)
    entry = {}
    for det_name, det in [("fast", cv2.FastFeatureDetector_create(threshold=30)),
                          ("brisk", cv2.BRISK_create())]:
        kps = det.detect(img, None)
        rows = [[float(str(np.float32(v))) for v in (k.pt[0], k.pt[1], k.size, k.angle, k.response)]
                + [k.octave] for k in kps]
        entry[det_name] = {"keypoints": rows}
        for name, make in extractors.items():
            tagged = [cv2.KeyPoint(k.pt[0], k.pt[1], k.size, k.angle, k.response, k.octave, j)
                      for j, k in enumerate(kps)]
            kept, desc = make().compute(img, tagged)
            entry[det_name][name] = {
                "kept": [k.class_id for k in kept],
                "rows": [hashlib.sha256(bytes(r)).hexdigest()[:16] for r in (desc if desc is not None else [])]}
    result["images"].append(entry)
json.dump(result, open(out, "w"))
