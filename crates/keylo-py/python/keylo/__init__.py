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
    judge,
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


def _is_path(config):
    """Whether a config argument names a file (a path, or a one-line string ending `.toml`)."""
    return isinstance(config, os.PathLike) or (isinstance(config, str) and "\n" not in config
                                               and config.endswith(".toml"))


def _config_table(config):
    """The config as a dict (for its ``[source]``), and its folder for relative paths."""
    if config is None:
        return {}, pathlib.Path(".")
    if isinstance(config, dict):
        return config, pathlib.Path(".")
    if _is_path(config):
        path = pathlib.Path(config)
        with path.open("rb") as f:
            return tomllib.load(f), path.parent
    return tomllib.loads(config), pathlib.Path(".")


def run(config=None, data=None, gt=None, trust_plugins=False, **source):
    """Runs a config over data in this process, as ``keylo run`` does.

    ``config`` is what ``Odometry`` takes. The frames come from ``data`` (any path
    ``keylo.open`` reads, with ``source`` keys) or else from the config's ``[source]``
    (the simulator by default). ``gt`` is a TUM/KITTI file; without it, as for ``keylo
    run``: ``[output] gt``, else a ``gt.tum`` beside the data, else the source's own ground
    truth (the simulator's).

    Returns ``(records, summary)``: one dict per frame (``index``, ``stamp``, ``x``, ``y``,
    ``z``, point counts, ``iterations``, ``converged``, ``degenerate`` — None, or the reason
    the registration could not constrain the pose —, ``odometry_ms``), pandas-friendly, and
    a dict with ``frames``, ``mean_cloud_points``, ``mean_registered_points``,
    ``mean_odometry_ms``, ``odometry_hz``, ``trajectory`` (N×4×4), ``stamps``, ``ground_truth``
    (``(stamps, poses)`` or a path, None without), ``accuracy`` (``keylo.evaluate``'s
    figures, or None), ``kinds`` (each stage's backend) and ``interrupted`` (Ctrl-C stops
    the run; the frames done are kept). An error in the data raises after the frames before
    it were registered; ``compare`` keeps those. Under ``[output] on_degenerate = "error"`` a
    degenerate frame stops the run as such an error (``StageError``), as ``keylo run`` does.
    ``trust_plugins`` is ``Odometry``'s: a
    config naming libraries of its own is refused without it.
    """
    records, summary, error = _run(config, data, gt, source, trust_plugins)
    if error is not None:
        raise error
    return records, summary


def _ground_truth(gt, table, folder, data, reader):
    """The ground truth ``keylo run`` would use: ``gt``, else ``[output] gt``, else a
    ``gt.tum`` beside the data, else the source's own (the simulator's): a path or
    ``(stamps, poses)``, None without."""
    if gt is not None:
        return gt
    if table.get("output", {}).get("gt"):
        return folder / table["output"]["gt"]
    if data is not None and (beside := pathlib.Path(data) / "gt.tum").is_file():
        return beside
    return reader.ground_truth()


def _truth_args(truth):
    """Ground truth as ``evaluate``/``judge`` take it: a path, or ``(stamps, poses)``."""
    if isinstance(truth, tuple):
        return {"gt": truth[1], "gt_stamps": truth[0]}
    return {"gt": truth}


def _run(config, data, gt, source, trust_plugins=False):
    """``run``'s work: ``(records, summary, error)``, where ``error`` is the ``KeyloError``
    that stopped the run after the frames in ``records`` (None when the data ran out). A
    config that does not build raises."""
    table, folder = _config_table(config)
    odometry = Odometry(config, trust_plugins=trust_plugins)
    if data is not None:
        reader, path = open(data, **source), data
    else:
        src = dict(table.get("source", {}))
        src.pop("projection", None)
        kind = src.pop("kind", "sim")
        path = src.pop("path", None)
        if path is not None and not os.path.isabs(path):
            path = folder / path
        reader = open(path, kind=kind, **src, **source)
    results, interrupted, error = [], False, None
    stop_on_degenerate = table.get("output", {}).get("on_degenerate", "warn") == "error"
    try:
        for frame in reader:
            result = odometry.process_frame(frame)
            if stop_on_degenerate and result.degenerate is not None:
                # As `keylo run`: the run stops there, keeping the frames before it.
                error = StageError(
                    f"frame {result.index}: degenerate frame: {result.degenerate} "
                    f'(output.on_degenerate = "error"; "warn" flags it and goes on)')
                break
            results.append(result)
    except KeyboardInterrupt:
        interrupted = True
    except KeyloError as e:
        error = e
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
            "degenerate": (r.degenerate or {}).get("reason"),
            "odometry_ms": 1e3 * r.timings["total"],
        })
    truth = _ground_truth(gt, table, folder, path, reader)
    accuracy = None
    if records and truth is not None:
        accuracy = evaluate(trajectory, est_stamps=stamps, **_truth_args(truth))
    mean = (lambda key: float(np.mean([r[key] for r in records]))) if records else (lambda key: 0.0)
    seconds = sum(r["odometry_ms"] for r in records) * 1e-3
    summary = {
        "frames": len(records),
        "mean_cloud_points": mean("cloud_points"),
        "mean_registered_points": mean("registered_points"),
        "mean_odometry_ms": mean("odometry_ms"),
        "odometry_hz": len(records) / seconds if seconds > 0 else 0.0,
        "trajectory": trajectory,
        "stamps": stamps,
        "ground_truth": truth,
        "accuracy": accuracy,
        "kinds": odometry.kinds,
        "interrupted": interrupted,
    }
    return records, summary, error


def _with_override(table, key, value):
    """A copy of config ``table`` with dotted ``key`` set to ``value``."""
    out = copy.deepcopy(table)
    node = out
    *path, last = key.split(".")
    for part in path:
        node = node.setdefault(part, {})
    node[last] = value
    return out


def _label(config):
    """A config's name in the tables: its file stem, else ``dict``, ``text`` or ``default``."""
    if config is None:
        return "default"
    if isinstance(config, dict):
        return "dict"
    if _is_path(config):
        return pathlib.Path(config).stem
    return "text"


#: The columns of ``compare``'s records, in ``keylo compare``'s order (compare.csv).
COMPARE_COLUMNS = (
    "data", "variant", "config", "registrar", "downsampler", "verdict", "reason", "frames",
    "degenerate_frames", "associated_poses", "trans_mean_m", "trans_rmse_m", "trans_max_m", "rot_mean_deg",
    "rot_rmse_deg", "rpe_trans_m", "rpe_rot_deg", "cpu_percent", "peak_rss_mb",
    "frames_late", "mean_points", "mean_registered_points", "odometry_hz", "rate_vs_raw",
)


def _compare_row(config, data, gt, source, criterion, trust_plugins=False):
    """One run of ``compare``: its figures and verdict (the columns of ``COMPARE_COLUMNS``)."""
    row = dict.fromkeys(COMPARE_COLUMNS)
    try:
        records, summary, error = _run(config, data, gt, source, trust_plugins)
    except KeyloError as e:
        row.update(verdict="failed", reason=str(e), frames=0)
        return row
    flagged = [r["degenerate"] for r in records if r["degenerate"]]
    row.update(frames=summary["frames"], degenerate_frames=len(flagged),
               registrar=summary["kinds"]["registrar"],
               downsampler=summary["kinds"]["downsampler"],
               mean_points=summary["mean_cloud_points"],
               mean_registered_points=summary["mean_registered_points"],
               odometry_hz=summary["odometry_hz"])
    accuracy = summary["accuracy"] or {}
    row.update(rpe_trans_m=accuracy.get("rpe_trans_rmse_m"),
               rpe_rot_deg=accuracy.get("rpe_rot_rmse_deg"))
    if records:
        row.update(judge(summary["trajectory"], est_stamps=summary["stamps"],
                         **_truth_args(summary["ground_truth"]), **criterion))
    after_first = sum(1 for r in records[1:] if r["degenerate"])
    all_degenerate = (len(records) == 1 and flagged) or (
        len(records) > 1 and after_first == len(records) - 1)
    if error is not None:
        row.update(verdict="failed", reason=f"stopped at frame {len(records)}: {error}")
    elif all_degenerate:
        row.update(verdict="failed", reason=f"every frame after the first degenerate "
                   f"({flagged[0]}): the trajectory is the motion model's prediction, not odometry")
    elif summary["interrupted"]:
        row.update(verdict="failed", reason=f"interrupted after {len(records)} frames")
    elif not records:
        row.update(verdict="failed", reason="no frame")
    return row


def compare(configs, data=None, grid=None, gt=None, max_ape=2.0, max_step=5.0,
            t_max_diff=0.01, trust_plugins=False, **source):
    """Configurations side by side, in this process, judged as ``keylo compare`` judges
    them: every config (path, TOML text or dict) × every combination of ``grid``
    (``{"registrar.voxel_size": [0.5, 1.0]}``) × every ``data`` (a path or a list of paths;
    None: each config's own source), each run by :func:`run`.

    Returns one record per run with ``keylo compare``'s columns (``COMPARE_COLUMNS``:
    ``data``, ``variant``, ``config``, stage kinds, ``verdict`` — ``ok``, ``diverged`` or
    ``failed`` —, ``reason``, ``frames``, ``degenerate_frames``, the aligned APE figures ``trans_*_m``/``rot_*_deg``
    over poses paired within ``t_max_diff`` s, RPE, points per frame, ``odometry_hz`` and
    ``rate_vs_raw``) plus one column per grid key. A run is diverged when a pose is not
    finite, a step between poses exceeds ``max_step`` m or the APE exceeds ``max_ape`` m;
    failed when it stopped before the end of the data (its figures cover the frames before).
    ``cpu_percent``, ``peak_rss_mb`` and ``frames_late`` (of ``keylo compare --realtime``)
    are None: runs share this process and are not paced. ``gt`` is one
    TUM/KITTI file for every data; without it each source's own ground truth is used.
    ``trust_plugins`` is ``Odometry``'s (a config's own libraries load only with it).
    """
    if data is None or isinstance(data, (str, os.PathLike)):
        datas = [data]
    else:
        datas = list(data)
    keys = list((grid or {}).keys())
    criterion = {"max_ape": max_ape, "max_step": max_step, "t_max_diff": t_max_diff}
    if isinstance(configs, (str, dict, os.PathLike)) or configs is None:
        configs = [configs]
    records = []
    for config in configs:
        table, folder = _config_table(config)
        label = _label(config)
        for values in itertools.product(*[grid[k] for k in keys]) if keys else [()]:
            run_config = table
            for k, v in zip(keys, values):
                run_config = _with_override(run_config, k, v)
            if keys and not isinstance(config, dict):
                # Relative paths of a file config resolve against its folder.
                src = run_config.get("source", {})
                if "path" in src and not os.path.isabs(src["path"]):
                    run_config = _with_override(run_config, "source.path", str(folder / src["path"]))
            point = " ".join(f"{k}={v}" for k, v in zip(keys, values))
            variant = label if not point else point if len(configs) == 1 else f"{label} {point}"
            for d in datas:
                row = _compare_row(run_config if keys else config, d, gt, source, criterion,
                                   trust_plugins)
                row.update(data=pathlib.Path(d).stem if d is not None else label,
                           variant=variant,
                           config=str(config) if not isinstance(config, dict) else "dict")
                row.update(dict(zip(keys, values)))
                records.append(row)
    _add_rate_ratios(records)
    return records


def _add_rate_ratios(records):
    """``rate_vs_raw``: each run's odometry rate over that of the ``passthrough`` run with
    the same data and registrar, as ``keylo compare`` fills it."""
    raw = {(r["data"], r["registrar"]): r["odometry_hz"] for r in records
           if r["downsampler"] == "passthrough" and r["odometry_hz"]}
    for r in records:
        base = raw.get((r["data"], r["registrar"]))
        if base and r["odometry_hz"] is not None:
            r["rate_vs_raw"] = r["odometry_hz"] / max(base, 1e-12)


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
    "COMPARE_COLUMNS",
    "evaluate",
    "judge",
    "keypoints",
    "open",
    "register_detector",
    "register_downsampler",
    "run",
    "sim",
]
