#!/usr/bin/env python3
"""Largest pose difference between two files of "t x y z qx qy qz qw" lines (TUM, or the
first line of `pcl_ndt pair` / `ndt_pair pair` output), matched line by line.
Prints: max translation difference (m) and max rotation difference (degrees)."""
import math
import sys


def poses(path):
    out = []
    for line in open(path):
        v = line.split()
        if len(v) == 8:
            try:
                out.append([float(x) for x in v])
            except ValueError:
                pass
    return out


def rot_diff_deg(qa, qb):
    # angle of qa^-1 * qb from the vector part (well conditioned for small angles)
    ax, ay, az, aw = qa
    bx, by, bz, bw = qb
    # conjugate of a times b
    x = aw * bx - ax * bw - ay * bz + az * by
    y = aw * by + ax * bz - ay * bw - az * bx
    z = aw * bz - ax * by + ay * bx - az * bw
    w = aw * bw + ax * bx + ay * by + az * bz
    return math.degrees(2 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w)))


a, b = poses(sys.argv[1]), poses(sys.argv[2])
if len(a) != len(b) or not a:
    sys.exit(f"{len(a)} vs {len(b)} poses")
dt = max(math.dist(p[1:4], q[1:4]) for p, q in zip(a, b))
dr = max(rot_diff_deg(p[4:8], q[4:8]) for p, q in zip(a, b))
print(f"poses {len(a)} max_dt_m {dt:.6f} max_dr_deg {dr:.5f}")
