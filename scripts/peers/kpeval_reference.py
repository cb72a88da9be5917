#!/usr/bin/env python3
"""Reference implementation of the paper's keypoint metrics with OpenCV's Python API.

Written independently of keylo from the authors' definitions
(../shared/paper/upstream-code-notes.md), to check `keylo keypoints eval` against:

    /usr/bin/python3 scripts/peers/kpeval_reference.py DIR [DIR...] > tests/fixtures/kpeval/reference.csv

Each DIR is a folder of 8-bit grey PNG images evaluated in name order (consecutive images
are matched). Needs cv2 (Debian's python3-opencv 4.6, the OpenCV keylo links; no contrib, so
BRIEF/FREAK/SURF are not covered here). Images are resized to 1024x64 (INTER_LINEAR).
"""
import glob
import os
import sys

import cv2
import numpy as np

W, H = 1024, 64
REPEAT_PX = 4.0
RATIO = 0.8


def detector(name):
    if name == "FAST":
        return cv2.FastFeatureDetector_create(threshold=30, nonmaxSuppression=True,
                                              type=cv2.FAST_FEATURE_DETECTOR_TYPE_9_16)
    if name in ("SHITOMASI", "HARRIS"):
        return cv2.GFTTDetector_create(maxCorners=W * H // 4, qualityLevel=0.01, minDistance=4,
                                       blockSize=4, useHarrisDetector=name == "HARRIS", k=0.04)
    return extractor(name)


def extractor(name):
    if name == "BRISK":
        return cv2.BRISK_create(thresh=30, octaves=3, patternScale=1.0)
    if name == "ORB":
        return cv2.ORB_create()
    if name == "SIFT":
        return cv2.SIFT_create()
    if name == "AKAZE":
        return cv2.AKAZE_create()
    raise ValueError(name)


def rotate_bound(img, deg):
    """The authors' rotation: the canvas is OpenCV's RotatedRect(…).boundingRect2f() (corner
    points in float32), the matrix shifted by half its growth, the size rounded."""
    h, w = img.shape
    m = cv2.getRotationMatrix2D((w / 2, h / 2), deg, 1.0)
    ang = deg * np.pi / 180.0
    b, a = np.float32(np.cos(ang)) * np.float32(0.5), np.float32(np.sin(ang)) * np.float32(0.5)
    fw, fh = np.float32(w), np.float32(h)
    p0 = (-a * fh - b * fw, b * fh - a * fw)
    p1 = (a * fh - b * fw, -b * fh - a * fw)
    xs = np.array([p0[0], p1[0], -p0[0], -p1[0]], np.float32)
    ys = np.array([p0[1], p1[1], -p0[1], -p1[1]], np.float32)
    bw, bh = np.float32(xs.max() - xs.min()), np.float32(ys.max() - ys.min())
    m[0, 2] += (float(bw) - w) / 2.0
    m[1, 2] += (float(bh) - h) / 2.0
    out = cv2.warpAffine(img, m, (int(round(float(bw))), int(round(float(bh)))),
                         flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return out, np.vstack([m, [0, 0, 1]])


def repeat(kps, kps_t, hom):
    """The authors' computeRobustness: positions mapped by perspectiveTransform (float32),
    the float32 distance to the nearest transformed keypoint strictly below REPEAT_PX."""
    if not kps:
        return None
    if not kps_t:
        return 0.0
    p = np.float32([k.pt for k in kps]).reshape(-1, 1, 2)
    q = cv2.perspectiveTransform(p, hom).reshape(-1, 2)
    t = np.float32([k.pt for k in kps_t])
    d = q[:, None, :] - t[None, :, :]
    dist = np.sqrt((d.astype(np.float64) ** 2).sum(-1)).astype(np.float32)
    return float((dist.min(1) < np.float32(REPEAT_PX)).sum()) / len(kps)


def robustness(det, img, kps):
    rot, h_rot = rotate_bound(img, 45.0)
    s = 2.0
    scaled = cv2.resize(img, None, fx=s, fy=s, interpolation=cv2.INTER_LINEAR)
    h, w = img.shape
    h_paper = np.array([[s, 0, (s - 1) * w / 2], [0, s, (s - 1) * h / 2], [0, 0, 1]])
    h_corr = np.array([[s, 0, (s - 1) / 2], [0, s, (s - 1) / 2], [0, 0, 1]])
    blurred = cv2.GaussianBlur(img, (5, 5), 0)
    k_scaled = det.detect(scaled, None)
    return (repeat(kps, det.detect(rot, None), h_rot), repeat(kps, k_scaled, h_paper),
            repeat(kps, k_scaled, h_corr), repeat(kps, det.detect(blurred, None), np.eye(3)))


def norm(des):
    return cv2.NORM_HAMMING if des.dtype == np.uint8 else cv2.NORM_L2


def pair(prev, cur):
    (kp0, d0), (kp1, d1) = prev, cur
    if d0 is None or d1 is None or len(kp0) == 0 or len(kp1) == 0:
        return len(kp0) and 0, None, 0, None, 0, 0
    m = cv2.BFMatcher(norm(d0), crossCheck=True).match(d0, d1)
    m = sorted(m, key=lambda x: x.distance)
    ratio = len(m) / len(kp1)  # the authors divide by the newer image's keypoints
    inliers, score = 0, None
    if len(m) >= 4:
        src = np.float32([kp0[x.queryIdx].pt for x in m])
        dst = np.float32([kp1[x.trainIdx].pt for x in m])
        _, mask = cv2.findHomography(src, dst, cv2.RANSAC, 3.0)
        inliers = int(mask.sum()) if mask is not None else 0
        score = inliers / len(m)
    knn = cv2.BFMatcher(norm(d0), crossCheck=False).knnMatch(d0, d1, k=2)
    two = [p for p in knn if len(p) == 2]
    passed = sum(1 for a, b in two if a.distance < RATIO * b.distance)
    return len(m), ratio, inliers, score, passed, len(two)


COMBOS = ["AKAZE_AKAZE", "ORB_ORB", "SIFT_SIFT", "BRISK_BRISK", "FAST_BRISK", "FAST_SIFT",
          "SHITOMASI_SIFT", "HARRIS_BRISK"]


def fmt(v):
    return "" if v is None else repr(float(v)) if isinstance(v, float) else str(v)


def main():
    print("dataset,index,combo,keypoints,described,robustness_rotation,robustness_scaling,"
          "robustness_scaling_corrected,robustness_blur,matches,match_ratio,inliers,match_score,"
          "knn_passed,knn_total")
    for folder in sys.argv[1:]:
        files = sorted(glob.glob(os.path.join(folder, "*.png")))
        images = [cv2.resize(cv2.imread(f, cv2.IMREAD_GRAYSCALE), (W, H),
                             interpolation=cv2.INTER_LINEAR) for f in files]
        for combo in COMBOS:
            dname, ename = combo.split("_")
            det = detector(dname)
            ext = None if dname == ename else extractor(ename)
            prev = None
            for i, img in enumerate(images):
                kps = list(det.detect(img, None))
                rob = robustness(det, img, kps)
                if ext is None:
                    kd, des = det.detectAndCompute(img, None)
                else:
                    kd, des = ext.compute(img, kps)
                cur = (list(kd), des)
                p = pair(prev, cur) if prev is not None else (None,) * 6
                row = [os.path.basename(os.path.normpath(folder)), i, combo, len(kps), len(kd),
                       *rob, *p]
                print(",".join(fmt(v) for v in row))
                prev = cur


if __name__ == "__main__":
    main()
