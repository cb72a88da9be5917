"""Bad input is a keylo exception naming what is wrong, never a crash."""

import numpy as np
import pytest

import keylo


def test_the_exceptions_form_a_hierarchy():
    for e in (keylo.ConfigError, keylo.DataError, keylo.StageError, keylo.PluginError):
        assert issubclass(e, keylo.KeyloError) and issubclass(e, Exception)


def test_a_misspelt_key_names_it():
    with pytest.raises(keylo.ConfigError, match="max_rnage"):
        keylo.Odometry({"registrar": {"kind": "kiss-icp", "max_rnage": 3.0}})
    with pytest.raises(keylo.ConfigError, match="nope"):
        keylo.Odometry({"registrar": {"kind": "nope"}})
    with pytest.raises(keylo.ConfigError, match="invalid TOML"):
        keylo.Odometry("[registrar\nkind = 1")
    with pytest.raises(keylo.ConfigError, match="cannot read config file"):
        keylo.Odometry("missing.toml")
    with pytest.raises(keylo.ConfigError, match="not a config value"):
        keylo.Odometry({"registrar": {"kind": object()}})


def test_point_arrays_of_the_wrong_shape_are_refused():
    odometry = keylo.Odometry()
    with pytest.raises(keylo.DataError, match=r"N×3 or N×4 array, got 10×2"):
        odometry.process(np.zeros((10, 2)))
    with pytest.raises(keylo.DataError, match="points"):
        odometry.process(np.zeros(7))
    with pytest.raises(keylo.DataError, match="times: 3 values for 10 points"):
        odometry.process(np.ones((10, 3)), times=np.zeros(3))
    with pytest.raises(keylo.DataError, match="points"):
        odometry.process("not points")
    assert odometry.frames == 0


def test_nan_points_are_dropped_and_time_must_go_forward():
    odometry = keylo.Odometry()
    rng = np.random.default_rng(0)
    points = rng.uniform(-10, 10, (2000, 3))
    points[::10] = np.nan
    first = odometry.process(points, stamp=1.0)
    assert first.cloud_points == 1800
    with pytest.raises(keylo.DataError, match="not after the previous frame"):
        odometry.process(points, stamp=0.5)
    # The pipeline goes on after an error.
    assert odometry.process(points, stamp=1.1).index == 1


def test_unreadable_data_names_the_path(tmp_path):
    with pytest.raises(keylo.DataError, match="no such file"):
        keylo.open(tmp_path / "nothing.pcap")
    (tmp_path / "x.txt").write_text("hello")
    with pytest.raises(keylo.DataError, match="no source recognises"):
        keylo.open(tmp_path / "x.txt")
    with pytest.raises(keylo.DataError, match="give a path"):
        keylo.open()


def test_a_degenerate_frame_says_so():
    odometry = keylo.Odometry()
    first = odometry.process(np.array([[5.0, 1.0, 0.5]]), stamp=0.0)
    assert first.degenerate == {"reason": "too-few-points", "points": 1, "minimum": 3}
    # A room: every wall seen, nothing degenerate.
    rng = np.random.default_rng(0)
    u, v = rng.uniform(-1, 1, (2, 3000))
    walls = [np.stack(w, 1) for w in ((10 + 0 * u, 6 * u, 2 * v), (-10 + 0 * u, 6 * u, 2 * v),
                                      (10 * u, 6 + 0 * u, 2 * v), (10 * u, -6 + 0 * u, 2 * v),
                                      (10 * u, 6 * v, 2 + 0 * u), (10 * u, 6 * v, -2 + 0 * u))]
    room = np.concatenate(walls)
    fresh = keylo.Odometry()
    for k in range(3):
        r = fresh.process(room - [0.1 * k, 0, 0], stamp=0.1 * k)
        assert r.degenerate is None, r.degenerate


def test_on_degenerate_error_stops_run_keeping_the_frames_before(tmp_path):
    # Three scans of a room, the third cut to one point.
    rng = np.random.default_rng(1)
    velodyne = tmp_path / "velodyne"
    velodyne.mkdir()
    u, v = rng.uniform(-1, 1, (2, 3000))
    room = np.concatenate([np.stack(w, 1) for w in (
        (10 + 0 * u, 6 * u, 2 * v), (-10 + 0 * u, 6 * u, 2 * v), (10 * u, 6 + 0 * u, 2 * v),
        (10 * u, -6 + 0 * u, 2 * v), (10 * u, 6 * v, 2 + 0 * u), (10 * u, 6 * v, -2 + 0 * u))])
    for k in range(3):
        scan = room - [0.1 * k, 0, 0] if k < 2 else np.array([[5.0, 1.0, 0.5]])
        np.hstack([scan, np.ones((len(scan), 1))]).astype(np.float32).tofile(
            velodyne / f"{k:06d}.bin")
    with pytest.raises(keylo.StageError, match="degenerate frame"):
        keylo.run({"output": {"on_degenerate": "error"}}, data=str(tmp_path))
    records, summary, error = keylo._run({"output": {"on_degenerate": "error"}}, str(tmp_path),
                                         None, {})
    assert len(records) == 2 and "too-few-points" in str(error)
    records, _ = keylo.run(None, data=str(tmp_path))
    assert [r["degenerate"] for r in records] == [None, None, "too-few-points"]
