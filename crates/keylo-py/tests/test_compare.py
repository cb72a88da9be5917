"""keylo.compare: the records `keylo compare` writes (same columns, figures and verdicts),
in-process, so Python detectors take part."""

import json
import math
import shutil

import pytest

import keylo
from conftest import run_cli

SIM = {"kind": "sim", "scene": "lab", "frames": 6, "sensor": "os1-64", "columns": 512}

# Columns that depend on the process or the clock, not on the data and the config.
MEASURED = {"cpu_percent", "peak_rss_mb", "odometry_hz", "rate_vs_raw", "config", "resumed"}
# Columns only `keylo compare` writes: the ground-truth file's name and how many poses paired
# with it (it reads a file, keylo.compare pairs the source's ground truth in memory).
CLI_ONLY = {"associated", "reference", "association", "association_warning"}


@pytest.fixture(scope="module")
def configs_and_data(keylo_bin, tmp_path_factory):
    """Ten simulated frames (with gt.tum) and two configs: raw cloud, and a voxel filter."""
    base = tmp_path_factory.mktemp("compare")
    sim = base / "lab"
    run_cli(keylo_bin, "sim", "--frames", 10, "--out", sim,
            "--set", "sensor=os1-64", "--set", "columns=512", "-q")
    # `exact`: trajectory files with every digit, so `keylo compare` (which reads them back)
    # and keylo.compare (which keeps the poses in memory) judge the same numbers.
    common = '[output]\nexact = true\n[registrar]\nkind = "kiss-icp"\nmax_range = 30.0\n'
    raw = base / "raw.toml"
    raw.write_text(common)
    voxel = base / "voxel.toml"
    voxel.write_text(common + '[downsampler]\nkind = "voxel"\nvoxel_size = 0.2\n')
    return base, sim, [raw, voxel]


def cli_compare(keylo_bin, base, sim, configs, *extra):
    out = base / f"cli-{sim.name}-{len(configs)}-{'_'.join(extra)}"
    run_cli(keylo_bin, "compare", *configs, "--data", sim, "--out", out, "--no-plots", "-q",
            *extra)
    return json.loads((out / "compare.json").read_text())["runs"]


def assert_same_rows(cli, ours):
    assert len(cli) == len(ours)
    for c, o in zip(cli, ours):
        for key, want in c.items():
            if key in MEASURED or key in CLI_ONLY:
                continue
            got = o[key]
            if isinstance(want, float):
                assert got == pytest.approx(want, rel=1e-12, abs=1e-15), (key, c, o)
            else:
                assert got == want, (key, c, o)


def test_records_equal_keylo_compares_rows(keylo_bin, configs_and_data):
    base, sim, configs = configs_and_data
    cli = cli_compare(keylo_bin, base, sim, configs)
    ours = keylo.compare(configs, data=sim)
    assert [r["verdict"] for r in ours] == ["ok", "ok"]
    assert ours[0]["associated_poses"] == 10 and ours[0]["trans_max_m"] < 0.2
    assert ours[1]["mean_points"] < ours[0]["mean_points"]
    assert ours[0]["downsampler"] == "passthrough" and ours[0]["rate_vs_raw"] == 1.0
    assert ours[1]["rate_vs_raw"] > 0 and math.isfinite(ours[1]["odometry_hz"])
    assert list(ours[0])[:len(keylo.COMPARE_COLUMNS)] == list(keylo.COMPARE_COLUMNS)
    assert_same_rows(cli, ours)


def test_divergence_verdicts_equal_keylo_compares(keylo_bin, configs_and_data):
    base, sim, configs = configs_and_data
    cli = cli_compare(keylo_bin, base, sim, configs, "--diverge-ape", "0.001")
    ours = keylo.compare(configs, data=sim, max_ape=0.001)
    assert [r["verdict"] for r in ours] == ["diverged", "diverged"]
    assert ours[0]["reason"].startswith("max APE") and "> 0.001 m" in ours[0]["reason"]
    assert_same_rows(cli, ours)
    steps = keylo.compare(configs[:1], data=sim, max_step=0.01)
    assert steps[0]["verdict"] == "diverged" and steps[0]["reason"].startswith("a step of")


def test_every_config_and_grid_value_is_a_record():
    base = {"source": SIM, "registrar": {"kind": "kiss-icp", "max_range": 30.0}}
    voxel = {**base, "downsampler": {"kind": "voxel", "voxel_size": 0.2}}
    records = keylo.compare([base, voxel], grid={"registrar.voxel_size": [0.25, 0.5]})
    assert len(records) == 4
    assert all(r["verdict"] == "ok" and r["frames"] == 6 for r in records), records
    assert [r["registrar.voxel_size"] for r in records] == [0.25, 0.5, 0.25, 0.5]
    assert [r["variant"] for r in records][:2] == ["dict registrar.voxel_size=0.25",
                                                  "dict registrar.voxel_size=0.5"]
    assert records[2]["mean_points"] < records[0]["mean_points"]
    assert all(r["trans_rmse_m"] < 0.2 for r in records)


def test_a_run_that_fails_is_a_record_saying_why():
    bad = keylo.compare([{"source": SIM, "registrar": {"kind": "nope"}}])
    assert bad[0]["verdict"] == "failed" and "nope" in bad[0]["reason"]
    assert bad[0]["frames"] == 0


def test_a_run_stopped_by_bad_data_keeps_its_frames(keylo_bin, configs_and_data):
    base, sim, configs = configs_and_data
    bad = base / "truncated"
    shutil.copytree(sim, bad)
    with (bad / "frames" / "000006.klf").open("r+b") as f:
        f.truncate(100)
    cli = cli_compare(keylo_bin, base, bad, configs[:1])
    ours = keylo.compare(configs[:1], data=bad)
    assert ours[0]["verdict"] == "failed" and ours[0]["frames"] == 6, ours
    assert ours[0]["reason"].startswith("stopped at frame 6: ") and "000006.klf" in ours[0]["reason"]
    assert ours[0]["associated_poses"] == 6
    assert_same_rows(cli, ours)


def test_judge_calls_a_run_that_never_moved_diverged():
    """SE(3) alignment needs an estimate that spreads in space: one stuck at the origin is
    judged with the first poses aligned, against how far the ground truth went."""
    import numpy as np

    stamps = [0.1 * i for i in range(5)]
    truth = np.tile(np.eye(4), (5, 1, 1))
    truth[:, 0, 3] = np.arange(5.0)
    stuck = np.tile(np.eye(4), (5, 1, 1))
    row = keylo.judge(stuck, truth, est_stamps=stamps, gt_stamps=stamps)
    assert row["verdict"] == "diverged"
    assert row["reason"] == "max APE 4.00 m > 2 m (first poses aligned: SE(3) alignment impossible)"
    assert row["trans_max_m"] is None  # no SE(3)-aligned figures to report
    moving = keylo.judge(truth, truth, est_stamps=stamps, gt_stamps=stamps)
    assert moving["verdict"] == "ok" and moving["trans_max_m"] < 1e-9
