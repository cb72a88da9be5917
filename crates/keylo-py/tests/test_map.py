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
