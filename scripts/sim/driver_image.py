"""The 8-bit signal image Ouster's ROS driver makes (`ouster-ros`, its image node), which the
TIERS images of the paper are: auto exposure maps the 10th and 90th percentiles of every 4th
pixel's non-zero values to 0.1 and 0.9 (or, when that would lift 0 above 0, scales by the 90th
percentile alone), the result is clipped to 0–1, its square root written as 16 bits, and the
authors kept the top byte. The same as keylo's `[image.normalise] method = "ouster-ros"`
(crates/keylo-features/src/image/ouster_ros.rs). Needs numpy.
"""

import numpy as np

PERCENTILE = 0.1


def driver_image(counts):
    """uint8 image of a 2-D array of signal counts (0: no return)."""
    sampled = counts.ravel()[::4]
    nonzero = np.sort(sampled[sampled > 0])
    if len(nonzero) < 100:
        return np.zeros(counts.shape, np.uint8)
    k = int(len(nonzero) * PERCENTILE)
    lo, hi = nonzero[k], nonzero[len(nonzero) - k - 1]
    with np.errstate(divide="ignore"):
        scale = (1 - 2 * PERCENTILE) / (hi - lo)
    if not np.isfinite(scale):
        x = counts * (0.5 / hi)
    elif PERCENTILE - scale * lo <= 0:
        x = (counts - lo) * scale + PERCENTILE
    else:
        x = counts * ((1 - PERCENTILE) / hi)
    mono16 = (np.sqrt(np.clip(x, 0, 1)) * 65535).astype(np.uint32)
    return (mono16 // 256).astype(np.uint8)
