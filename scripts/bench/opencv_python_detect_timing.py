"""Times OpenCV from Python on the same images and with the same parameters as keylo's
`detect_timing` example; prints milliseconds per image per combination as JSON.

Usage: python3 opencv_python_detect_timing.py IMAGE_DIR REPEATS
Run it with the Python whose cv2 is the same OpenCV keylo links (Debian: /usr/bin/python3
with python3-opencv, OpenCV 4.6), so the ratio measures keylo's overhead, not two builds.
"""
import glob, json, os, sys, time

import cv2

image_dir, repeats = sys.argv[1], int(sys.argv[2])
images = [cv2.imread(p, cv2.IMREAD_GRAYSCALE) for p in sorted(glob.glob(os.path.join(image_dir, "signal_*.png")))]

gftt = dict(maxCorners=16384, qualityLevel=0.01, minDistance=4.0, blockSize=4)
combos = {
    "shi-tomasi": (lambda: cv2.GFTTDetector_create(**gftt, useHarrisDetector=False), None, False),
    "harris": (lambda: cv2.GFTTDetector_create(**gftt, useHarrisDetector=True), None, False),
    "fast": (lambda: cv2.FastFeatureDetector_create(threshold=30), None, False),
    "fast_orb": (lambda: cv2.FastFeatureDetector_create(threshold=30), cv2.ORB_create, False),
    "shi-tomasi_sift": (lambda: cv2.GFTTDetector_create(**gftt), cv2.SIFT_create, False),
    "akaze_akaze": (cv2.AKAZE_create, None, True),
    "orb_orb": (cv2.ORB_create, None, True),
    "brisk_brisk": (cv2.BRISK_create, None, True),
    "sift_sift": (cv2.SIFT_create, None, True),
    "kaze_kaze": (cv2.KAZE_create, None, True),
    "fast_brisk": (lambda: cv2.FastFeatureDetector_create(threshold=30), cv2.BRISK_create, False),
}
ms, counts = {}, {}
for name, (make_det, make_desc, same) in combos.items():
    det = make_det()
    desc = make_desc() if make_desc else None
    n_kp = 0
    t = time.perf_counter()
    for _ in range(repeats):
        for img in images:
            if same:
                kps, d = det.detectAndCompute(img, None)
            else:
                kps = det.detect(img, None)
                if desc is not None:
                    kps, d = desc.compute(img, kps)
            n_kp += len(kps)
    n = repeats * len(images)
    ms[name] = (time.perf_counter() - t) * 1e3 / n
    counts[name] = n_kp / n
print(json.dumps({"tool": "opencv-python " + cv2.__version__, "images": len(images),
                  "ms_per_image": ms, "keypoints_per_image": counts}))
