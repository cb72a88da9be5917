#!/usr/bin/env python3
"""KITTI-style .bin folders with unusual layouts, made from real scans, for
scripts/kiss_icp_parity.sh: every case reads the same files in keylo and official KISS-ICP.

Usage: odd_layouts.py VELODYNE_DIR OUT   (needs numpy: the peers venv has it)

Cases (OUT/<case>/*.bin, float32 x y z intensity):
  nonfinite      2 % of the coordinates of every scan set to NaN/+inf/-inf, and 500 rows of
                 NaN/inf inserted at random places
  zeros          5 % of the rows of every scan set to 0 0 0 0 (how exports mark "no return")
  empty-scan     scan 4 holds no point (a 0-byte file)
  one-point      scan 4 holds only its first point
  one-point-far  scan 4 holds one point 500 m away (beyond max_range: nothing to register)
"""
import glob
import os
import sys

import numpy as np


def main(src_dir: str, out: str) -> None:
    scans = sorted(glob.glob(os.path.join(src_dir, "*.bin")))
    if not scans:
        sys.exit(f"no .bin scans in {src_dir}")
    rng = np.random.default_rng(7)

    def write(case: str, i: int, pts: np.ndarray) -> None:
        d = os.path.join(out, case)
        os.makedirs(d, exist_ok=True)
        pts.astype(np.float32).tofile(os.path.join(d, f"{i:06d}.bin"))

    for i, f in enumerate(scans):
        p = np.fromfile(f, dtype=np.float32).reshape(-1, 4)
        q = p.copy()
        k = rng.choice(len(q), len(q) // 50, replace=False)
        q[k, rng.integers(0, 3, len(k))] = rng.choice([np.nan, np.inf, -np.inf], len(k))
        bad = np.full((500, 4), np.nan, np.float32)
        bad[::2, :3] = np.inf
        write("nonfinite", i, np.insert(q, rng.integers(0, len(q), 500), bad, axis=0))
        z = p.copy()
        z[rng.choice(len(z), len(z) // 20, replace=False)] = 0
        write("zeros", i, z)
        write("empty-scan", i, p[:0] if i == 4 else p)
        write("one-point", i, p[:1] if i == 4 else p)
        far = np.array([[500.0, 0.0, 0.0, 0.0]], np.float32)
        write("one-point-far", i, far if i == 4 else p)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
