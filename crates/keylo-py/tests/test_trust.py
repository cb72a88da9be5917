"""A config's own libraries (`[plugins] dirs`, `onnxruntime`) load only with
``trust_plugins=True``; the library here leaves a marker file from its load-time constructor,
so the marker's absence proves that nothing was loaded (docs/python.md, "Trust")."""

import os
import pathlib
import shutil
import subprocess

import pytest

import keylo

MARKER_C = (pathlib.Path(__file__).resolve().parents[2]
            / "keylo-cli/tests/fixtures/plugins/marker.c")


@pytest.fixture
def shared(tmp_path, monkeypatch):
    """A config as someone might share it, with its library in ``p/`` beside it."""
    compiler = shutil.which("cc") or shutil.which("gcc")
    assert compiler, "a C compiler (the Rust tests need one too)"
    (tmp_path / "p").mkdir()
    subprocess.run([compiler, "-shared", "-fPIC", str(MARKER_C), "-o",
                    str(tmp_path / "p/libmarker.so")], check=True)
    (tmp_path / "plugin.toml").write_text(
        '[plugins]\ndirs = ["p"]\n[detector]\nkind = "plugin:marker"\n')
    (tmp_path / "runtime.toml").write_text(
        '[detector]\nkind = "superpoint"\nonnxruntime = "p/libmarker.so"\n')
    monkeypatch.setenv("KEYLO_TEST_MARKER", str(tmp_path / "marker"))
    monkeypatch.setenv("KEYLO_PLUGIN_PATH", str(tmp_path / "installed"))
    return tmp_path


def test_nothing_a_config_names_loads_without_the_opt_in(shared):
    for name, named in [("plugin.toml", "libmarker.so ([plugins] dirs)"),
                        ("runtime.toml", "libmarker.so (detector.onnxruntime)")]:
        for call in (lambda c: keylo.Odometry(c), lambda c: keylo.run(c, frames=2),
                     lambda c: keylo.compare([c], frames=2)):
            try:
                out = call(str(shared / name))
            except keylo.KeyloError as e:
                message = str(e)
            else:  # compare keeps going: the refusal is the row's reason
                message = out[0]["reason"]
            assert named in message and "trust_plugins=True" in message, message
            assert not (shared / "marker").exists()


def test_the_opt_in_loads_it(shared):
    with pytest.raises(keylo.PluginError, match="keylo_plugin_entry"):
        keylo.Odometry(str(shared / "plugin.toml"), trust_plugins=True)
    assert (shared / "marker").exists()


def test_a_keypoint_spec_naming_its_own_runtime_is_refused(shared):
    import numpy as np
    images = [np.zeros((64, 256), np.uint8)] * 2
    spec = f'[params.superpoint]\nonnxruntime = "{shared / "p/libmarker.so"}"\n'
    with pytest.raises(keylo.ConfigError, match="params.superpoint.onnxruntime"):
        keylo.keypoints.evaluate(images, combos="ORB_ORB", spec=spec)
    assert not (shared / "marker").exists()
