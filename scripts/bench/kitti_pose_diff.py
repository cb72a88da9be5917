#!/usr/bin/env python3
"""Largest pose difference between two KITTI pose files (3x4 row-major per line), matched
line by line, without alignment. With CALIB (a KITTI calib.txt with a `Tr:` line), REF is in
the cam0 frame (KISS-ICP's `--dataloader kitti` output) and is taken to the LiDAR frame
first: inv(Tr) * T * Tr. Prints JSON: poses, max translation difference (m), max rotation
difference (deg). Usage: kitti_pose_diff.py EST REF [CALIB]"""
import json
import math
import sys


def poses(path):
    out = []
    for line in open(path):
        v = [float(x) for x in line.split()]
        if len(v) == 12:
            out.append([v[0:4], v[4:8], v[8:12], [0.0, 0.0, 0.0, 1.0]])
    return out


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def inv(t):
    # general inverse of the 3x3 part (KITTI's Tr is not exactly orthonormal)
    a = [row[:3] for row in t[:3]]
    det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
           - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
           + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    r = [[(a[(j + 1) % 3][(i + 1) % 3] * a[(j + 2) % 3][(i + 2) % 3]
           - a[(j + 1) % 3][(i + 2) % 3] * a[(j + 2) % 3][(i + 1) % 3]) / det
          for j in range(3)] for i in range(3)]
    p = [-sum(r[i][k] * t[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [p[0]], r[1] + [p[1]], r[2] + [p[2]], [0.0, 0.0, 0.0, 1.0]]


def calib_tr(path):
    for line in open(path):
        if line.startswith("Tr:"):
            v = [float(x) for x in line.split()[1:13]]
            return [v[0:4], v[4:8], v[8:12], [0.0, 0.0, 0.0, 1.0]]
    sys.exit(f"{path}: no Tr: line")


def main():
    est, ref = poses(sys.argv[1]), poses(sys.argv[2])
    if len(sys.argv) > 3:
        tr = calib_tr(sys.argv[3])
        ref = [mul(mul(inv(tr), t), tr) for t in ref]
    dt, dr = 0.0, 0.0
    for a, b in zip(est, ref):
        d = mul(inv(a), b)
        dt = max(dt, math.sqrt(sum((a[i][3] - b[i][3]) ** 2 for i in range(3))))
        c = (d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0
        s = 0.5 * math.sqrt((d[2][1] - d[1][2]) ** 2 + (d[0][2] - d[2][0]) ** 2
                            + (d[1][0] - d[0][1]) ** 2)
        dr = max(dr, math.degrees(math.atan2(s, c)))
    print(json.dumps({"poses": min(len(est), len(ref)), "max_dt_m": dt, "max_drot_deg": dr}))


if __name__ == "__main__":
    main()
