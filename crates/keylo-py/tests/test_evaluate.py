"""keylo.evaluate gives the figures `keylo eval` gives, on files and on arrays."""

import json

import numpy as np
import pytest

import keylo
from conftest import run_cli


@pytest.fixture(scope="module")
def sim_run(keylo_bin, tmp_path_factory):
    """A simulated lab (frames + gt.tum) and `keylo run` on it (trajectory.tum/.kitti)."""
    base = tmp_path_factory.mktemp("eval")
    sim, out = base / "sim", base / "run"
    run_cli(keylo_bin, "sim", "--frames", 20, "--out", sim,
            "--set", "sensor=os1-64", "--set", "columns=512", "-q")
    run_cli(keylo_bin, "run", "--data", sim, "--out", out, "-q")
    return sim, out


def cli_eval(keylo_bin, est, gt):
    done = run_cli(keylo_bin, "eval", "--est", est, "--gt", gt, "--json")
    return json.loads(done.stdout[done.stdout.index("{"):])


def test_files_give_keylo_evals_figures(keylo_bin, sim_run):
    sim, out = sim_run
    for est in ("trajectory.tum", "trajectory.kitti"):
        cli = cli_eval(keylo_bin, out / est, sim / "gt.tum")
        ours = keylo.evaluate(out / est, sim / "gt.tum")
        assert ours == cli
        assert cli["associated_poses"] == 20 and cli["ate_rmse_m"] < 0.1


def test_arrays_give_the_figures_of_the_files_they_hold(keylo_bin, sim_run):
    sim, out = sim_run
    est = np.loadtxt(out / "trajectory.tum")
    gt = np.loadtxt(sim / "gt.tum")

    def matrices(rows):
        from_q = []
        for t, x, y, z, qx, qy, qz, qw in rows:
            r = np.array([
                [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
                [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
                [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
            ])
            m = np.eye(4)
            m[:3, :3], m[:3, 3] = r, (x, y, z)
            from_q.append(m)
        return np.array(from_q)

    files = keylo.evaluate(out / "trajectory.tum", sim / "gt.tum")
    arrays = keylo.evaluate(matrices(est), matrices(gt), est_stamps=est[:, 0], gt_stamps=gt[:, 0])
    for key in ("associated_poses", "ate_rmse_m", "rpe_trans_rmse_m", "rpe_rot_rmse_deg"):
        assert arrays[key] == pytest.approx(files[key], rel=1e-6, abs=1e-9), key


def test_bad_arguments_are_data_errors(sim_run):
    sim, out = sim_run
    with pytest.raises(keylo.DataError, match="align"):
        keylo.evaluate(out / "trajectory.tum", sim / "gt.tum", align="affine")
    with pytest.raises(keylo.DataError, match="N×4×4"):
        keylo.evaluate(np.zeros((3, 3, 3)), sim / "gt.tum")
    with pytest.raises(keylo.DataError, match="pose 0 is not a rigid transform"):
        keylo.evaluate(np.zeros((3, 4, 4)), np.zeros((3, 4, 4)))
    with pytest.raises(keylo.DataError, match="no such file|cannot read"):
        keylo.evaluate(sim / "missing.tum", sim / "gt.tum")
