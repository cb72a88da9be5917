"""No memory growth over 10 000 `process` calls (beyond the trajectory itself)."""

import numpy as np

import keylo


def rss_mb():
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    import resource

    return pages * resource.getpagesize() / 2**20


def test_ten_thousand_calls_do_not_grow_memory():
    rng = np.random.default_rng(1)
    points = rng.uniform(-5, 5, (100, 3))
    # The Python path is what is measured: a small cloud, no degeneracy analysis.
    odometry = keylo.Odometry(
        {"registrar": {"kind": "kiss-icp", "max_range": 20.0, "degeneracy": {"analyse": False}}}
    )
    for k in range(1000):
        result = odometry.process(points, stamp=0.1 * k)
        _ = result.pose, result.timings, result.keypoints
    before = rss_mb()
    for k in range(1000, 10_000):
        result = odometry.process(points, stamp=0.1 * k)
        _ = result.pose, result.timings, result.keypoints
    grown = rss_mb() - before
    # 9 000 poses and stamps of the trajectory are about 0.6 MB; a leak of 1 KB per call
    # would be 9 MB.
    assert grown < 4.0, f"RSS grew {grown:.1f} MB over 9000 calls"
    assert odometry.frames == 10_000
