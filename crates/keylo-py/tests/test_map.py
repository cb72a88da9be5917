"""A global map saved from Python (`Odometry.save_map`) is the map `keylo run --map-out`
saves from the same frames: the same cloud and keyframe files, byte for byte."""

import json

import pytest

import keylo
from conftest import run_cli
from test_pipeline import CONFIG


def test_a_map_saved_from_python_is_keylo_runs(sim_bins, keylo_bin, tmp_path):
    odometry = keylo.Odometry(CONFIG)
    odometry.save_map(tmp_path / "py", {"voxel_size": 0.1, "keyframe_distance": 0.5})
    for frame in keylo.open(sim_bins):
        odometry.process_frame(frame)
    manifest = odometry.finish_map()
    assert odometry.finish_map() is None
    assert manifest["format"] == "keylo-map" and manifest["version"] == 1
    assert manifest["frames"] == odometry.frames and manifest["points"] > 1000
    assert manifest["settings"]["voxel_size"] == 0.1

    cfg = tmp_path / "run.toml"
    cfg.write_text(CONFIG)
    run_cli(keylo_bin, "run", cfg, "--data", sim_bins, "--out", tmp_path / "run", "-q",
            "--map-out", tmp_path / "cli", "--set", "map.voxel_size=0.1",
            "--set", "map.keyframe_distance=0.5")
    cli = json.loads((tmp_path / "cli" / "map.json").read_text())
    assert (cli["points"], cli["keyframes"]) == (manifest["points"], manifest["keyframes"])
    for name in ["map.ply", "map.pcd", "keyframes.csv", "keyframes/000000.ply"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    info = run_cli(keylo_bin, "map", "info", tmp_path / "py").stdout
    assert f"points       {manifest['points']}" in info


def test_bad_map_settings_are_config_errors(tmp_path):
    odometry = keylo.Odometry(CONFIG)
    with pytest.raises(keylo.ConfigError, match=r"map.voxel_size = -1: expected a finite value above 0"):
        odometry.save_map(tmp_path / "m", {"voxel_size": -1.0})
    with pytest.raises(keylo.ConfigError, match=r"unknown field `voxel`"):
        odometry.save_map(tmp_path / "m", {"voxel": 1.0})


def test_frames_carry_the_fitted_covariance(sim_bins):
    """The covariance keylo's pose graph and ROS 2 node use: symmetric, positive definite,
    and wider than plain sigma^2 H^-1 with sigma = 0.03 m (the motion terms)."""
    import numpy as np
    odometry = keylo.Odometry(CONFIG)
    results = [odometry.process_frame(f) for f in keylo.open(sim_bins)]
    assert results[0].fitted_covariance is None or results[0].degeneracy is not None
    for r in results[1:]:
        c = r.fitted_covariance
        assert c.shape == (6, 6)
        np.testing.assert_allclose(c, c.T, rtol=1e-9, atol=1e-18)
        assert np.linalg.eigvalsh(c).min() > 0
        assert np.trace(c) > np.trace(r.covariance(0.03))


def test_localisation_in_a_saved_map_from_a_config(sim_bins, tmp_path):
    """`[registrar] kind = "localise"`: the frames localised in the map saved from them stay
    on the mapping run's poses, each with its fit; a pose given far off is reported as not
    tracking, and `set_pose` finds the map again. Odometry frames carry no fit."""
    import numpy as np
    odometry = keylo.Odometry(CONFIG)
    odometry.save_map(tmp_path / "map")
    frames = list(keylo.open(sim_bins))
    mapped = [odometry.process_frame(f) for f in frames]
    odometry.finish_map()
    assert all(r.fitness is None and r.tracking is None for r in mapped)
    for method in ["icp", "ndt"]:
        localiser = keylo.Odometry(f"""
[registrar]
kind = "localise"
map = "{(tmp_path / 'map').as_posix()}"
method = "{method}"
voxel_size = 0.3
ndt.resolution = 1.0
""")
        for r0, f in zip(mapped[:6], frames[:6]):
            r = localiser.process_frame(f)
            assert r.tracking, (method, r.index, r.fitness)
            assert 0.5 <= r.fitness <= 1.0
            assert np.linalg.norm(r.pose[:3, 3] - r0.pose[:3, 3]) < 0.05, (method, r.index)
        far = np.array(mapped[5].pose)
        far[:3, 3] += [8.0, -5.0, 0.0]  # outside the room
        far[:3, :3] = far[:3, :3] @ np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
        localiser.set_pose(far)
        assert localiser.process_frame(frames[6]).tracking is False
        localiser.set_pose(mapped[6].pose)
        assert localiser.process_frame(frames[7]).tracking is True


def test_a_localise_config_without_a_map_is_an_error():
    with pytest.raises(keylo.KeyloError, match=r"`map` is empty; expected the folder of a saved map"):
        keylo.Odometry('[registrar]\nkind = "localise"\n')
