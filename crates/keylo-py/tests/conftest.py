"""Fixtures of the keylo Python tests: the `keylo` CLI built by cargo, simulated data."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def keylo_bin():
    """The `keylo` command line (KEYLO_BIN, else target/debug/keylo as cargo builds it)."""
    path = pathlib.Path(os.environ.get("KEYLO_BIN", ROOT / "target" / "debug" / "keylo"))
    if not path.exists():
        pytest.fail(f"{path} is missing: build it with `cargo build -p keylo-cli`")
    return path


def run_cli(keylo_bin, *args, cwd=None):
    """Runs `keylo ARGS`, failing the test with its stderr when it fails."""
    done = subprocess.run([str(keylo_bin), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    if done.returncode != 0:
        pytest.fail(f"keylo {' '.join(map(str, args))} exited {done.returncode}:\n{done.stderr}")
    return done


@pytest.fixture(scope="session")
def sim_bins(keylo_bin, tmp_path_factory):
    """Eight simulated lab frames (OS1-64, 512 columns) written as KITTI `.bin` files."""
    out = tmp_path_factory.mktemp("sim") / "bins"
    run_cli(keylo_bin, "sim", "--frames", 8, "--format", "kitti-bin", "--out", out,
            "--set", "sensor=os1-64", "--set", "columns=512", "-q")
    return out


@pytest.fixture(scope="session")
def ouster_pcap():
    """A real Ouster capture shipped with the tests (OS1-128, 1024×10, three frames)."""
    return ROOT / "tests" / "fixtures" / "ouster" / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap"
