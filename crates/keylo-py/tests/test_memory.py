"""No memory growth over 10 000 `process` calls (beyond the trajectory itself)."""

import resource

import numpy as np

import keylo


def rss_mb():
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * resource.getpagesize() / 2**20


def test_ten_thousand_calls_do_not_grow_memory():
    rng = np.random.default_rng(1)
    points = rng.uniform(-5, 5, (100, 3))
    # The Python path is what is measured: a small cloud, no degeneracy analysis.
    odometry = keylo.Odometry(
        {"registrar": {"kind": "kiss-icp", "max_range": 20.0, "degeneracy": {"analyse": False}}}
    )
    samples = []
    for k in range(10_000):
        result = odometry.process(points, stamp=0.1 * k)
        _ = result.pose, result.timings, result.keypoints
        if k >= 2000 and k % 1000 == 999:
            samples.append(rss_mb())
    # Eight samples after 2 000 calls of warm-up: the allocator's own ups and downs are about
    # ±1.5 MB; a leak of 1 KB per call would put the last three 5 MB above the first three.
    # (The trajectory's 10 000 poses and stamps are about 0.6 MB of it.)
    grown = np.mean(samples[-3:]) - np.mean(samples[:3])
    assert grown < 3.0, f"RSS grew {grown:.1f} MB from calls 3000–5000 to 8000–10000: {samples}"
    assert odometry.frames == 10_000
