"""keylo.keypoints.evaluate gives the figures of the OpenCV-python reference that
`keylo keypoints eval` is tested against (tests/fixtures/kpeval/reference.csv)."""

import csv
import pathlib

import numpy as np
import pytest

import keylo

ROOT = pathlib.Path(__file__).resolve().parents[3]
FIXTURES = ROOT / "tests" / "fixtures" / "kpeval"
COMBOS = "AKAZE_AKAZE,ORB_ORB,SIFT_SIFT,BRISK_BRISK,FAST_BRISK,FAST_SIFT,SHITOMASI_SIFT,HARRIS_BRISK"
KEYS = ["keypoints", "described", "robustness_rotation", "robustness_scaling",
        "robustness_scaling_corrected", "robustness_blur", "matches", "match_ratio", "inliers",
        "match_score", "knn_passed", "knn_total"]


def test_every_metric_agrees_with_the_opencv_python_reference():
    cv2 = pytest.importorskip("cv2")
    with open(FIXTURES / "reference.csv") as f:
        reference = list(csv.DictReader(f))
    compared = 0
    for dataset in ("os0", "sim"):
        files = sorted((FIXTURES / "images" / dataset).glob("*.png"))
        images = [cv2.imread(str(p), cv2.IMREAD_UNCHANGED) for p in files]
        assert all(i is not None and i.dtype == np.uint8 for i in images)
        rows, summaries, skipped = keylo.keypoints.evaluate(images, combos=COMBOS)
        assert skipped == []
        assert {s["combo"] for s in summaries} == set(COMBOS.split(","))
        for r in (r for r in reference if r["dataset"] == dataset):
            ours = next(o for o in rows if o["combo"] == r["combo"] and o["index"] == int(r["index"]))
            for k in KEYS:
                want, got = r[k], ours[k]
                if want == "":
                    assert got is None, (dataset, r["combo"], r["index"], k, got)
                else:
                    assert got == pytest.approx(float(want), abs=1e-6), (dataset, r["combo"], k)
                compared += 1
    assert compared == 56 * 12


def test_bad_images_and_combos_are_named():
    with pytest.raises(keylo.DataError, match=r"images\[1\]: expected an H×W uint8 array"):
        keylo.keypoints.evaluate([np.zeros((64, 64), np.uint8), np.zeros((64, 64))])
    with pytest.raises(keylo.ConfigError, match="NOPE"):
        keylo.keypoints.evaluate([np.zeros((64, 64), np.uint8)] * 2, combos="NOPE_NOPE")


def test_a_python_detector_takes_part_in_the_study():
    cv2 = pytest.importorskip("cv2")

    class CvFast:
        def __init__(self, threshold):
            self.fast = cv2.FastFeatureDetector_create(threshold=threshold, nonmaxSuppression=True)

        def detect(self, image):
            kps = self.fast.detect(image)
            return np.array([(k.pt[0], k.pt[1], k.size, k.angle, k.response) for k in kps],
                            np.float32).reshape(-1, 5)

    keylo.register_detector("cvfast", CvFast(threshold=30))  # the paper preset's FAST
    files = sorted((FIXTURES / "images" / "sim").glob("*.png"))
    images = [cv2.imread(str(p), cv2.IMREAD_UNCHANGED) for p in files]
    ours, _, _ = keylo.keypoints.evaluate(images, combos="python:cvfast_BRISK")
    builtin, _, _ = keylo.keypoints.evaluate(images, combos="FAST_BRISK")
    assert len(ours) == len(builtin) == len(images)
    for a, b in zip(ours, builtin):
        for k in ("keypoints", "described", "robustness_rotation", "matches", "match_ratio"):
            assert a[k] == b[k], k
