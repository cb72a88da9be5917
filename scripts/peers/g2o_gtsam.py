#!/usr/bin/env python3
"""Reads keylo's pose_graph.g2o with GTSAM (PyPI `gtsam`, an independent reader) and checks it
against the run it came from; with a ground-truth trajectory, GTSAM's own factors give the
normalised estimation error squared (NEES) of every keyframe edge (docs/results/maps.md).

    g2o_gtsam.py RUN_DIR [RUN_DIR...]     (each with pose_graph.g2o, trajectory.tum and,
                                           for NEES, reference.tum)

Prints one JSON object per run: vertices, edges, the largest difference between a vertex and
the run's pose, between an edge's measurement and its vertices' relative pose, and the NEES
of each edge against the reference (2 × the factor's error, as GTSAM whitens it).
"""

import json
import sys
from pathlib import Path

import gtsam
import numpy as np


def tum(path):
    rows = [list(map(float, l.split())) for l in Path(path).read_text().splitlines()
            if l.strip() and not l.startswith("#")]
    return np.array(rows).reshape(-1, 8)


def pose(row):
    x, y, z, qx, qy, qz, qw = row
    return gtsam.Pose3(gtsam.Rot3.Quaternion(qw, qx, qy, qz), gtsam.Point3(x, y, z))


def check(run):
    run = Path(run)
    graph, initial = gtsam.readG2o(str(run / "pose_graph.g2o"), True)
    est = tum(run / "trajectory.tum")
    ref = tum(run / "reference.tum") if (run / "reference.tum").exists() else None
    # Each vertex is the run's pose at some frame: find its stamp.
    stamps, worst_vertex = [], 0.0
    for k in range(initial.size()):
        v = initial.atPose3(k)
        d = [np.linalg.norm(pose(r[1:]).localCoordinates(v)) for r in est]
        i = int(np.argmin(d))
        stamps.append(est[i, 0])
        worst_vertex = max(worst_vertex, d[i])
    worst_edge, nees = 0.0, []
    truth = gtsam.Values()
    if ref is not None:
        for k, s in enumerate(stamps):
            j = int(np.argmin(np.abs(ref[:, 0] - s)))
            truth.insert(k, pose(ref[j, 1:]))
    for f in range(graph.size()):
        factor = graph.at(f)
        if not isinstance(factor, gtsam.BetweenFactorPose3):
            continue
        a, b = factor.keys()
        rel = initial.atPose3(a).between(initial.atPose3(b))
        worst_edge = max(worst_edge, float(np.linalg.norm(factor.measured().localCoordinates(rel))))
        if ref is not None:
            nees.append(2.0 * factor.error(truth))
    return {
        "run": str(run),
        "vertices": initial.size(),
        "edges": len([1 for f in range(graph.size()) if isinstance(graph.at(f), gtsam.BetweenFactorPose3)]),
        "vertex_vs_run": worst_vertex,
        "edge_vs_vertices": worst_edge,
        "nees": nees,
        "nees_mean": float(np.mean(nees)) if nees else None,
    }


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for r in sys.argv[1:]:
        print(json.dumps(check(r)))
