"""A keypoint detector written in numpy only, used by keylo's pipeline from Python.

Corners are pixels whose structure tensor (Shi-Tomasi: the smaller eigenvalue) is the largest
of their cell in a coarse grid, so keypoints spread over the whole image. Registered as
`python:grid-corners`, it runs in the paper's pipeline: signal and range images, keypoint
windows, KISS-ICP.

    python examples/python/numpy_corners.py            # simulated lab, prints the drift
"""

import numpy as np

import keylo


class GridCorners:
    """The strongest Shi-Tomasi corner of every `cell`×`cell` block above `min_response`."""

    def __init__(self, cell=8, min_response=1.0):
        self.cell = cell
        self.min_response = min_response

    def detect(self, image):
        img = image.astype(np.float32)
        gy, gx = np.gradient(img)
        # Structure tensor summed over 3×3 neighbourhoods.
        def box(a):
            p = np.pad(a, 1, mode="edge")
            return sum(p[dy : dy + a.shape[0], dx : dx + a.shape[1]] for dy in range(3) for dx in range(3))

        sxx, syy, sxy = box(gx * gx), box(gy * gy), box(gx * gy)
        trace, det = sxx + syy, sxx * syy - sxy * sxy
        response = trace / 2 - np.sqrt(np.maximum(trace * trace / 4 - det, 0))
        h, w = img.shape
        c = self.cell
        points = []
        for y0 in range(0, h - c + 1, c):
            for x0 in range(0, w - c + 1, c):
                block = response[y0 : y0 + c, x0 : x0 + c]
                k = int(np.argmax(block))
                dy, dx = divmod(k, c)
                if block[dy, dx] > self.min_response:
                    points.append((x0 + dx, y0 + dy, 7.0, -1.0, block[dy, dx]))
        return np.array(points, dtype=np.float32).reshape(-1, 5)


CONFIG = {
    "image": {"kind": "lidar", "images": ["signal", "range"]},
    "detector": {"kind": "python:grid-corners"},
    "downsampler": {"kind": "keypoint-neighbourhood", "windows": "5_5", "on_too_few": "all-points"},
    "registrar": {"kind": "kiss-icp", "max_range": 30.0},
}


def run(frames=20):
    """Runs the detector on `frames` simulated lab frames; (keypoints per frame, final drift m)."""
    keylo.register_detector("grid-corners", GridCorners())
    odometry = keylo.Odometry(CONFIG)
    reader = keylo.open(kind="sim", scene="lab", frames=frames, sensor="os1-64", columns=512)
    counts = [odometry.process_frame(f).keypoint_count for f in reader]
    _, truth = reader.ground_truth()
    truth = np.linalg.inv(truth[0]) @ truth
    drift = float(np.linalg.norm(odometry.trajectory[-1][:3, 3] - truth[-1][:3, 3]))
    return counts, drift


if __name__ == "__main__":
    counts, drift = run()
    print(f"keypoints per frame: {min(counts)}..{max(counts)}; position error after the last frame: {drift:.3f} m")
