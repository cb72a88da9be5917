"""keylo.Odometry gives the trajectory `keylo run` gives, bit for bit, on the same data and
config; configs from a path, text or dict are the same config."""

import numpy as np
import pytest

import keylo
from conftest import run_cli

CONFIG = """
[downsampler]
kind = "passthrough"

[registrar]
kind = "kiss-icp"
max_range = 30.0

[output]
exact = true
"""


def cli_poses(keylo_bin, tmp_path, data, config=CONFIG):
    """The 3×4 poses `keylo run` writes for `data` (exact numbers)."""
    cfg = tmp_path / "run.toml"
    cfg.write_text(config)
    out = tmp_path / "out"
    run_cli(keylo_bin, "run", cfg, "--data", data, "--out", out, "-q")
    rows = np.loadtxt(out / "trajectory.kitti", ndmin=2)
    return rows.reshape(-1, 3, 4)


def python_poses(data, config=CONFIG):
    odometry = keylo.Odometry(config)
    for frame in keylo.open(data):
        odometry.process_frame(frame)
    return odometry.trajectory


@pytest.mark.parametrize("which", ["sim_bins", "ouster_pcap"])
def test_same_trajectory_as_keylo_run_bit_for_bit(which, request, keylo_bin, tmp_path):
    data = request.getfixturevalue(which)
    cli = cli_poses(keylo_bin, tmp_path, data)
    ours = python_poses(data)
    assert ours.shape == (len(cli), 4, 4)
    assert len(cli) >= 3
    np.testing.assert_array_equal(ours[:, :3, :], cli)
    np.testing.assert_array_equal(ours[:, 3, :], np.tile([0.0, 0.0, 0.0, 1.0], (len(cli), 1)))


def test_points_and_frames_of_an_unorganised_source_register_the_same(sim_bins):
    """Every point of a `.bin` scan, pushed as an array, gives the poses of its frame."""
    by_frame = keylo.Odometry(CONFIG)
    by_points = keylo.Odometry(CONFIG)
    for frame in keylo.open(sim_bins):
        a = by_frame.process_frame(frame)
        b = by_points.process(frame.points, stamp=frame.timestamp)
        assert a.cloud_points == b.cloud_points
    np.testing.assert_array_equal(by_frame.trajectory, by_points.trajectory)
    np.testing.assert_array_equal(by_frame.stamps, by_points.stamps)


def test_a_config_from_a_path_text_or_dict_is_the_same(sim_bins, tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(CONFIG)
    as_dict = {
        "downsampler": {"kind": "passthrough"},
        "registrar": {"kind": "kiss-icp", "max_range": 30.0},
    }
    trajectories = [python_poses(sim_bins, c) for c in (str(path), path, CONFIG, as_dict)]
    for t in trajectories[1:]:
        np.testing.assert_array_equal(t, trajectories[0])


def test_results_carry_counts_timings_degeneracy_and_the_map(sim_bins):
    odometry = keylo.Odometry(CONFIG)
    results = [odometry.process_frame(f) for f in keylo.open(sim_bins)]
    last = results[-1]
    assert last.cloud_points > 1000 and last.registered_points > 0
    assert last.map_points == len(odometry.local_map()) > 0
    assert set(last.timings) == {"image", "detect", "describe", "downsample", "register", "total"}
    assert last.timings["register"] > 0
    assert results[0].degeneracy is None and last.degeneracy is not None
    assert last.degeneracy["eigenvalues"].shape == (6,)
    cov = last.covariance(0.02)
    assert cov.shape == (6, 6) and np.all(np.diag(cov) > 0)
    assert odometry.frames == len(results) and odometry.stamps.shape == (len(results),)
    assert last.keypoints == []  # no image builder, no keypoints


def test_keypoints_come_with_descriptors_and_points(sim_bins):
    config = CONFIG + """
[image]
kind = "lidar"
images = ["signal", "range"]

[detector]
kind = "orb"

[descriptor]
kind = "orb"
"""
    odometry = keylo.Odometry(config)
    results = [odometry.process_frame(f) for f in keylo.open(sim_bins)]
    images = results[-1].keypoints
    assert [i["image"] for i in images] == ["signal", "range"]
    total = sum(len(i["xy"]) for i in images)
    assert total == results[-1].keypoint_count > 0
    for i in images:
        n = len(i["xy"])
        assert i["points"].shape == (n, 3)
        assert i["descriptors"].dtype == np.uint8 and i["descriptors"].shape[0] == n


def test_slam_hooks(sim_bins):
    frames = list(keylo.open(sim_bins))
    odometry = keylo.Odometry(CONFIG)
    odometry.process_frame(frames[0])
    moved = np.eye(4)
    moved[0, 3] = 100.0
    odometry.set_pose(moved)
    odometry.process_frame(frames[1])
    assert odometry.trajectory[-1][0, 3] > 99.0
    odometry.set_motion_prior(np.eye(4))
    odometry.reset()
    assert odometry.frames == 0
    assert np.array_equal(odometry.process_frame(frames[2]).pose, np.eye(4))
    with pytest.raises(keylo.DataError, match="not a rigid transform"):
        odometry.set_motion_prior(np.eye(4) * 2)


def test_run_gives_keylo_runs_trajectory_and_accuracy(keylo_bin, tmp_path):
    """keylo.run on a config's own source (the simulator) against `keylo run` on the config."""
    import json

    config = CONFIG + '\n[source]\nkind = "sim"\nscene = "lab"\nframes = 12\nsensor = "os1-64"\ncolumns = 512\n'
    cfg = tmp_path / "sim.toml"
    cfg.write_text(config)
    out = tmp_path / "out"
    run_cli(keylo_bin, "run", cfg, "--out", out, "-q")
    cli_poses = np.loadtxt(out / "trajectory.kitti", ndmin=2).reshape(-1, 3, 4)
    cli_summary = json.loads((out / "summary.json").read_text())
    records, summary = keylo.run(cfg)
    assert len(records) == summary["frames"] == len(cli_poses) == 12
    np.testing.assert_array_equal(summary["trajectory"][:, :3, :], cli_poses)
    assert summary["mean_cloud_points"] == cli_summary["mean_cloud_points"]
    ours, theirs = summary["accuracy"], cli_summary["accuracy"]
    for key in ("associated_poses", "ate_rmse_m", "rpe_trans_rmse_m", "rpe_rot_rmse_deg"):
        assert ours[key] == pytest.approx(theirs[key], rel=1e-9, abs=1e-12), key
    assert not summary["interrupted"]
    assert {"index", "stamp", "x", "cloud_points", "odometry_ms"} <= set(records[0])


def test_ctrl_c_stops_a_long_run_and_keeps_the_frames_done(tmp_path):
    import signal
    import subprocess
    import sys
    import time

    script = tmp_path / "long.py"
    # Ctrl-C as an interactive Python gets it: a test suite started in the background by a
    # non-interactive shell passes SIGINT on ignored, and Python then installs no handler.
    script.write_text(
        "import keylo, signal, sys\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "print('started', flush=True)\n"
        "records, summary = keylo.run({'source': {'kind': 'sim', 'frames': 100000,"
        " 'sensor': 'os1-64', 'columns': 512}})\n"
        "print(summary['interrupted'], summary['frames'], len(summary['trajectory']), flush=True)\n"
    )
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "started"
        time.sleep(3.0)
        p.send_signal(signal.SIGINT)
        out, _ = p.communicate(timeout=60)
    finally:
        # A run that ignored the signal must not outlive the test.
        p.kill()
    interrupted, frames, poses = out.split()
    assert p.returncode == 0
    assert interrupted == "True" and int(frames) == int(poses) > 0


GICP = CONFIG.replace('kind = "kiss-icp"', 'kind = "gicp"\nvoxel_size = 0.5')


@pytest.mark.parametrize("mode", ["local-map", "frame-to-frame"])
def test_gicp_is_taken_like_any_registrar(mode, sim_bins, keylo_bin, tmp_path):
    """GICP from Python: `keylo run`'s trajectory bit for bit, the hooks, its errors."""
    config = GICP.replace("voxel_size = 0.5", f'voxel_size = 0.5\nmode = "{mode}"')
    cli = cli_poses(keylo_bin, tmp_path, sim_bins, config)
    ours = python_poses(sim_bins, config)
    assert len(cli) >= 3
    np.testing.assert_array_equal(ours[:, :3, :], cli)
    frames = list(keylo.open(sim_bins))
    odometry = keylo.Odometry(config)
    first = odometry.process_frame(frames[0])
    assert first.registered_points > 0 and len(odometry.local_map()) > 0
    moved = np.eye(4)
    moved[0, 3] = 100.0
    odometry.set_pose(moved)
    if mode == "frame-to-frame":  # the previous scan moves with the pose
        assert odometry.process_frame(frames[1]).pose[0, 3] > 99.0
    else:  # the map stays: nothing of it near a pose 100 m away
        with pytest.raises(keylo.StageError, match="too few to register"):
            odometry.process_frame(frames[1])
    odometry.reset()
    assert np.array_equal(odometry.process_frame(frames[2]).pose, np.eye(4))
    # A parameter out of range is refused when the registrar is built (as for every
    # registrar: a StageError naming the key and the range).
    with pytest.raises(keylo.StageError, match="k_correspondences.*expected 3..=1000"):
        keylo.Odometry({"registrar": {"kind": "gicp", "k_correspondences": 1}})
