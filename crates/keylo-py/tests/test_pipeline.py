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
