#!/usr/bin/env python3
"""The authors' keypoint metrics with OpenCV-Python, on the paper's own images, held against
the authors' per-image results: how far another OpenCV build is from them, for the figures that
keylo cannot match exactly (docs/results/paper-reproduction.md).

    python scripts/peers/authors_metrics_cv2.py ../shared/data/tiers_signal ../shared/paper/per-image

Needs cv2 with contrib for BRIEF/FREAK (../shared/peers/setup-venv.sh gives opencv-contrib-python).
Prints per combination: the share of images with the authors' keypoint count, and cv2's / the
authors' medians (share of images with the same value) of match score, match ratio and
distinctiveness, computed as the authors' C++ program does (detect, then compute; cross-checked
brute force, previous image as query; ratio over the newer image's keypoints; RANSAC 3 px;
kNN k=2 with ratio 0.8 over every query row).
"""
import csv
import statistics as st
import sys

import cv2
import numpy as np

IMAGES, PER_IMAGE = sys.argv[1], sys.argv[2]
N = 200


def load(combo):
    with open(f"{PER_IMAGE}/{combo}.csv") as f:
        return {int(r["image_number"]): r for r in csv.DictReader(f)}


imgs = [cv2.resize(cv2.imread(f"{IMAGES}/image_{k:04d}.png", cv2.IMREAD_GRAYSCALE), (1024, 64),
                   interpolation=cv2.INTER_LINEAR) for k in range(N)]


def same(a, b):
    return sum(abs(x - y) < 5e-6 for x, y in zip(a, b)) / len(a)
def run(combo, det, ext, norm):
    th = load(combo)
    prev, same_kp, ms, tms, ds, tds, mr, tmr = None, 0, [], [], [], [], [], []
    for k, g in enumerate(imgs):
        kp = det.detect(g, None)
        if k>0 and len(kp) == int(float(th[k]["evaluation_1"])): same_kp += 1
        kd, d = ext.compute(g, kp)
        if prev is not None:
            pk, pd = prev
            m = cv2.BFMatcher(norm, True).match(pd, d)
            src = np.float32([pk[x.queryIdx].pt for x in m]); dst = np.float32([kd[x.trainIdx].pt for x in m])
            H, mask = cv2.findHomography(src, dst, cv2.RANSAC, 3)
            ms.append(mask.sum()/len(m)); tms.append(float(th[k]["evaluation_5"]))
            mr.append(len(m)/len(kd)); tmr.append(float(th[k]["evaluation_4"]))
            knn = cv2.BFMatcher(norm, False).knnMatch(pd, d, k=2)
            ds.append(sum(1 for a,b in knn if a.distance < 0.8*b.distance)/len(knn)); tds.append(float(th[k]["evaluation_6"]))
        prev = (kd, d)
    print(f"{combo}: cv2 {cv2.__version__} same_kp {same_kp/(N - 1):.3f} | match_score {st.median(ms):.3f}/{st.median(tms):.3f} same {same(ms,tms):.2f} | match_ratio {st.median(mr):.3f}/{st.median(tmr):.3f} same {same(mr,tmr):.2f} | distinct {st.median(ds):.3f}/{st.median(tds):.3f} same {same(ds,tds):.2f}")
H = cv2.NORM_HAMMING; L2 = cv2.NORM_L2
fast = cv2.FastFeatureDetector_create(30, True, cv2.FAST_FEATURE_DETECTOR_TYPE_9_16)
run("AKAZE_AKAZE", cv2.AKAZE_create(), cv2.AKAZE_create(), H)
run("BRISK_BRISK", cv2.BRISK_create(30,3,1.0), cv2.BRISK_create(30,3,1.0), H)
run("ORB_ORB", cv2.ORB_create(), cv2.ORB_create(), H)
run("SIFT_SIFT", cv2.SIFT_create(), cv2.SIFT_create(), L2)
if hasattr(cv2, "xfeatures2d"):
    run("FAST_BRIEF", fast, cv2.xfeatures2d.BriefDescriptorExtractor_create(), H)
    run("FAST_FREAK", fast, cv2.xfeatures2d.FREAK_create(), H)
