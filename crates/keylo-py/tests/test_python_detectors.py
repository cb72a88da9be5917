"""Detectors written in Python run in keylo's pipeline (`kind = "python:NAME"`)."""

import importlib.util
import pathlib

import numpy as np
import pytest

import keylo

ROOT = pathlib.Path(__file__).resolve().parents[3]


def frames(n=4):
    return list(keylo.open(kind="sim", scene="road", frames=n))


def config(detector):
    return {
        "image": {"kind": "lidar", "images": ["signal", "range"]},
        "detector": {"kind": detector},
        "downsampler": {"kind": "keypoint-neighbourhood", "windows": "4_7", "on_too_few": "all-points"},
        "registrar": {"kind": "kiss-icp"},
    }


def test_opencv_python_fast_gives_keylos_fast_keypoints_and_trajectory():
    cv2 = pytest.importorskip("cv2")

    class CvFast:
        def __init__(self):
            self.fast = cv2.FastFeatureDetector_create(threshold=10, nonmaxSuppression=True)

        def detect(self, image):
            kps = self.fast.detect(image)
            return np.array(
                [(k.pt[0], k.pt[1], k.size, k.angle, k.response) for k in kps], np.float32
            ).reshape(-1, 5)

    keylo.register_detector("cv-fast", CvFast())
    data = frames()
    ours, theirs = keylo.Odometry(config("fast")), keylo.Odometry(config("python:cv-fast"))
    for f in data:
        a, b = ours.process_frame(f), theirs.process_frame(f)
        assert a.keypoint_count == b.keypoint_count > 0
        for ia, ib in zip(a.keypoints, b.keypoints):
            np.testing.assert_array_equal(ia["xy"], ib["xy"])
            np.testing.assert_array_equal(ia["response"], ib["response"])
    np.testing.assert_array_equal(ours.trajectory, theirs.trajectory)


def test_a_python_descriptor_and_detector_pair():
    class Patches:
        """Detects a fixed grid; describes by the 8×8 patch around each point (float32, L2)."""

        def detect(self, image):
            h, w = image.shape
            ys, xs = np.mgrid[8 : h - 8 : 8, 8 : w - 8 : 16]
            return np.stack([xs.ravel(), ys.ravel()], axis=1).astype(np.float32)

        def describe(self, image, keypoints):
            d = [image[int(y) - 4 : int(y) + 4, int(x) - 4 : int(x) + 4].ravel() for x, y in keypoints[:, :2]]
            return keypoints, np.array(d, np.float32)

    keylo.register_detector("patches", Patches())
    cfg = config("python:patches")
    cfg["descriptor"] = {"kind": "python:patches"}
    odometry = keylo.Odometry(cfg)
    result = [odometry.process_frame(f) for f in frames(2)][-1]
    for image in result.keypoints:
        assert image["descriptors"].dtype == np.float32
        assert image["descriptors"].shape == (len(image["xy"]), 64)


def test_a_detector_that_raises_or_returns_garbage_names_itself_and_the_frame():
    class Raises:
        def detect(self, image):
            raise RuntimeError("boom")

    class Garbage:
        def __init__(self, value):
            self.value = value

        def detect(self, image):
            return self.value

    keylo.register_detector("raises", Raises())
    with pytest.raises(keylo.StageError, match=r"frame 0: Python backend `raises`: detect raised RuntimeError: boom"):
        keylo.Odometry(config("python:raises")).process_frame(frames(1)[0])
    cases = {
        "text": ("not an array", r"expected an N×2 to N×5 array"),
        "wide": (np.zeros((3, 7)), r"returned a 3×7 array"),
        "outside": (np.array([[1e6, 1.0]]), r"keypoint 0 at \(1000000, 1\) lies outside"),
        "nan": (np.array([[np.nan, 1.0]]), r"keypoint 0 at \(NaN, 1\) lies outside"),
    }
    for name, (value, message) in cases.items():
        keylo.register_detector(name, Garbage(value))
        with pytest.raises(keylo.StageError, match=message):
            keylo.Odometry(config(f"python:{name}")).process_frame(frames(1)[0])


def test_registration_is_checked():
    with pytest.raises(keylo.PluginError, match="neither `detect` nor `describe`"):
        keylo.register_detector("empty", object())
    with pytest.raises(keylo.PluginError, match="without spaces"):
        keylo.register_detector("a b", object())
    keylo.register_detector("cfg", type("D", (), {"detect": lambda self, im: np.zeros((0, 2))})())
    cfg = config("python:cfg")
    cfg["detector"]["threshold"] = 3
    with pytest.raises(keylo.ConfigError, match="takes no config keys"):
        keylo.Odometry(cfg)


def test_the_numpy_example_runs_and_tracks():
    spec = importlib.util.spec_from_file_location("numpy_corners", ROOT / "examples/python/numpy_corners.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    counts, drift = example.run(frames=8)
    assert min(counts) > 20
    assert drift < 0.2, f"{drift} m off the simulator's ground truth"


def test_the_onnx_example_matches_keylos_superpoint():
    pytest.importorskip("onnxruntime")
    spec = importlib.util.spec_from_file_location("superpoint_onnx", ROOT / "examples/python/superpoint_onnx.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    compared = 0
    for ours, builtin in example.run(frames=2):
        for a, b in zip(ours, builtin, strict=True):
            assert a["image"] == b["image"]
            np.testing.assert_array_equal(a["xy"], b["xy"])
            np.testing.assert_allclose(a["response"], b["response"], rtol=1e-4, atol=1e-6)
            np.testing.assert_allclose(a["descriptors"], b["descriptors"], atol=1e-4)
            compared += len(a["xy"])
    assert compared > 100


def test_a_python_downsampler_of_every_point_is_passthrough():
    class Every:
        def downsample(self, frame, keypoints):
            return frame.points  # every point of an unorganised scan, in file order

    keylo.register_downsampler("every", Every())
    reader = keylo.open(kind="sim", scene="lab", frames=5, sensor="os1-64", columns=512)
    frames = list(reader)
    # Each frame's valid points pushed as an unorganised scan: the frame then has every point.
    base = {"registrar": {"kind": "kiss-icp", "max_range": 30.0}}
    ours = keylo.Odometry({**base, "downsampler": {"kind": "python:every"}})
    theirs = keylo.Odometry({**base, "downsampler": {"kind": "passthrough"}})
    for f in frames:
        pts = f.xyz[f.valid].astype(np.float64)
        a, b = ours.process(pts, stamp=f.timestamp), theirs.process(pts, stamp=f.timestamp)
        assert a.cloud_points == b.cloud_points
    np.testing.assert_array_equal(ours.trajectory, theirs.trajectory)
    with pytest.raises(keylo.PluginError, match="no `downsample`"):
        keylo.register_downsampler("x", object())

    class Wrong:
        def downsample(self, frame, keypoints):
            return np.zeros((4, 2))

    keylo.register_downsampler("wrong", Wrong())
    with pytest.raises(keylo.StageError, match=r"frame 0: Python backend `wrong`: downsample returned a 4×2 array"):
        keylo.Odometry({**base, "downsampler": {"kind": "python:wrong"}}).process(np.ones((10, 3)))
