"""keylo: keypoint-assisted LiDAR odometry, from Python.

The pipeline of a keylo config fed frame by frame (``Odometry``), the frames of every source
keylo reads as numpy arrays (``open``), and keylo's exceptions. See docs/python.md.
"""

import copy
import itertools
import os
import pathlib
import tomllib

import numpy as np

from keylo._keylo import (
    ConfigError,
    DataError,
    Frame,
    FrameResult,
    KeyloError,
    Odometry,
    PluginError,
    Reader,
    StageError,
    __version__,
    evaluate,
    open,
    register_detector,
)



def register_downsampler(name, obj):
    """Makes ``kind = "python:NAME"`` a downsampler for every config built afterwards:
    ``obj.downsample(frame, keypoints)`` gets the ``keylo.Frame`` and, per image, a dict
    (``image``, ``xy`` N×2, ``scale`` image pixel → grid) and returns the cloud to register,
    N×3 (x, y, z, sensor frame) or N×4 (with each point's time relative to the frame)."""
    if not hasattr(obj, "downsample"):
        raise PluginError(f"register_downsampler(`{name}`): the object has no `downsample`")
    register_detector(name, obj)


def sim(scene="lab", frames=100, **keys):
    """Simulated frames and their ground truth: ``(frames, stamps, poses)``.

    ``scene`` is ``lab``, ``corridor`` or ``road``; more keys are the simulator's ``[source]``
    keys (``sensor``, ``columns``, ``motion_distortion``, …). ``poses`` is N×4×4.
    """
    reader = open(kind="sim", scene=scene, frames=frames, **keys)
    out = list(reader)
    stamps, poses = reader.ground_truth()
    return out, stamps, poses


from keylo import keypoints  # noqa: E402  (keylo.keypoints.evaluate)


def _config_table(config):
    """The config as a dict (for its ``[source]``), and its folder for relative paths."""
    if config is None:
        return {}, pathlib.Path(".")
    if isinstance(config, dict):
        return config, pathlib.Path(".")
    if isinstance(config, os.PathLike) or (isinstance(config, str) and "\n" not in config
                                           and config.endswith(".toml")):
        path = pathlib.Path(config)
        with path.open("rb") as f:
            return tomllib.load(f), path.parent
    return tomllib.loads(config), pathlib.Path(".")


def run(config=None, data=None, gt=None, **source):
    """Runs a config over data in this process, as ``keylo run`` does.

    ``config`` is what ``Odometry`` takes. The frames come from ``data`` (any path
    ``keylo.open`` reads, with ``source`` keys) or else from the config's ``[source]``
    (the simulator by default). ``gt`` is a TUM/KITTI file; without it, the source's own
    ground truth is used when it has one.

    Returns ``(records, summary)``: one dict per frame (``index``, ``stamp``, ``x``, ``y``,
    ``z``, point counts, ``iterations``, ``converged``, ``odometry_ms``), pandas-friendly, and
    a dict with ``frames``, ``mean_cloud_points``, ``mean_odometry_ms``, ``trajectory``
    (N×4×4), ``stamps``, ``accuracy`` (``keylo.evaluate``'s figures, or None) and
    ``interrupted`` (Ctrl-C stops the run; the frames done are kept).
    """
    table, folder = _config_table(config)
    if data is not None:
        reader = open(data, **source)
    else:
        src = dict(table.get("source", {}))
        src.pop("projection", None)
        kind = src.pop("kind", "sim")
        path = src.pop("path", None)
        if path is not None and not os.path.isabs(path):
            path = folder / path
        reader = open(path, kind=kind, **src, **source)
    odometry = Odometry(config)
    results, interrupted = [], False
    try:
        for frame in reader:
            results.append(odometry.process_frame(frame))
    except KeyboardInterrupt:
        interrupted = True
    # A Ctrl-C between a frame's registration and its append leaves it out of both.
    n = len(results)
    trajectory, stamps = odometry.trajectory[:n], odometry.stamps[:n]
    records = []
    for r in results:
        x, y, z = r.pose[:3, 3]
        records.append({
            "index": r.index, "stamp": r.stamp, "x": x, "y": y, "z": z,
            "keypoints": r.keypoint_count, "cloud_points": r.cloud_points,
            "registered_points": r.registered_points, "map_points": r.map_points,
            "iterations": r.iterations, "converged": r.converged,
            "odometry_ms": 1e3 * r.timings["total"],
        })
    accuracy = None
    if records:
        if gt is not None:
            accuracy = evaluate(trajectory, gt, est_stamps=stamps)
        elif (truth := reader.ground_truth()) is not None:
            gt_stamps, poses = truth
            accuracy = evaluate(trajectory, poses, est_stamps=stamps, gt_stamps=gt_stamps)
    summary = {
        "frames": len(records),
        "mean_cloud_points": float(np.mean([r["cloud_points"] for r in records])) if records else 0.0,
        "mean_odometry_ms": float(np.mean([r["odometry_ms"] for r in records])) if records else 0.0,
        "trajectory": trajectory,
        "stamps": stamps,
        "accuracy": accuracy,
        "interrupted": interrupted,
    }
    return records, summary


def _with_override(table, key, value):
    """A copy of config ``table`` with dotted ``key`` set to ``value``."""
    out = copy.deepcopy(table)
    node = out
    *path, last = key.split(".")
    for part in path:
        node = node.setdefault(part, {})
    node[last] = value
    return out


def compare(configs, data=None, grid=None, **source):
    """Configurations side by side, in this process: every config (path, TOML text or dict)
    × every combination of ``grid`` (``{"registrar.voxel_size": [0.5, 1.0]}``) × every
    ``data`` (a path or a list of paths; None: each config's own source), each run by
    :func:`run`.

    Returns one record per run: ``config``, ``data``, the grid values, ``verdict`` (``ok`` or
    ``failed``), ``reason``, ``frames``, ``mean_cloud_points``, ``mean_odometry_ms``, and the
    accuracy figures (``ate_rmse_m``, ``rpe_trans_rmse_m``, …) when there is ground truth.
    """
    if data is None or isinstance(data, (str, os.PathLike)):
        datas = [data]
    else:
        datas = list(data)
    keys = list((grid or {}).keys())
    records = []
    if isinstance(configs, (str, dict, os.PathLike)):
        configs = [configs]
    for config in configs:
        table, folder = _config_table(config)
        label = config if not isinstance(config, dict) else "dict"
        for values in itertools.product(*[grid[k] for k in keys]) if keys else [()]:
            run_config = table
            for k, v in zip(keys, values):
                run_config = _with_override(run_config, k, v)
            if keys and not isinstance(config, dict):
                # Relative paths of a file config resolve against its folder.
                src = run_config.get("source", {})
                if "path" in src and not os.path.isabs(src["path"]):
                    run_config = _with_override(run_config, "source.path", str(folder / src["path"]))
            for d in datas:
                record = {"config": str(label), "data": None if d is None else str(d)}
                record.update(dict(zip(keys, values)))
                try:
                    rows, summary = run(run_config if keys else config, d, **source)
                    record.update(verdict="ok", reason="", frames=summary["frames"],
                                  mean_cloud_points=summary["mean_cloud_points"],
                                  mean_odometry_ms=summary["mean_odometry_ms"])
                    record.update(summary["accuracy"] or {})
                except KeyloError as e:
                    record.update(verdict="failed", reason=str(e))
                records.append(record)
    return records


__all__ = [
    "ConfigError",
    "DataError",
    "Frame",
    "FrameResult",
    "KeyloError",
    "Odometry",
    "PluginError",
    "Reader",
    "StageError",
    "__version__",
    "compare",
    "evaluate",
    "keypoints",
    "open",
    "register_detector",
    "register_downsampler",
    "run",
    "sim",
]
