"""OpenCV's SURF (opencv-contrib 3.4.2, the last PyPI wheel with it) detect + describe per
image, one thread, on the same images as keylo's `detector_timing` example; prints JSON.

Usage: python3.7 surf_opencv_timing.py IMAGE_DIR [COUNT] [REPEATS]
"""
import json
import os
import sys
import time

import cv2

image_dir = sys.argv[1]
count = int(sys.argv[2]) if len(sys.argv) > 2 else 200
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
cv2.setNumThreads(1)
images = [cv2.resize(cv2.imread(os.path.join(image_dir, "image_%04d.png" % i), cv2.IMREAD_GRAYSCALE),
                     (1024, 64), interpolation=cv2.INTER_LINEAR) for i in range(count)]
surf = cv2.xfeatures2d.SURF_create()
n_kp = 0
t = time.perf_counter()
for _ in range(repeats):
    for img in images:
        kps, desc = surf.detectAndCompute(img, None)
        n_kp += len(kps)
n = len(images) * repeats
print(json.dumps({"tool": "opencv " + cv2.__version__, "images": len(images),
                  "ms_per_image": 1e3 * (time.perf_counter() - t) / n, "keypoints_per_image": n_kp / n}))
