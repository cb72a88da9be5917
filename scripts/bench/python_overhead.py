"""What the Python path costs on top of keylo's own work (issue 22's figures).

1. Per frame, `Odometry.process_frame` called from Python against `keylo run` on the same
   frames (a simulated lab folder, built-in stages: passthrough + KISS-ICP): the mean
   wall-clock time of the Python call over the CLI's mean odometry time per frame
   (`frames.csv`), each the best of `--repeats` interleaved runs.
2. Per image, the call overhead of a Python detector: keylo's `detect` time per image minus
   the time the Python `detect` spends in its own body (it returns a fixed array, so nearly
   all of the remainder is the crossing: image to numpy, the call, the array back).

    python scripts/bench/python_overhead.py --keylo target/release/keylo [--frames 100]

Run it with a release build of the package (`pip install ./crates/keylo-py`); it prints the
measured figures and their targets.
"""

import argparse
import csv
import pathlib
import subprocess
import tempfile
import time

import numpy as np

import keylo

CONFIG = """
[downsampler]
kind = "passthrough"

[registrar]
kind = "kiss-icp"
max_range = 30.0
"""


def cli_ms_per_frame(keylo_bin, config, data, out):
    subprocess.run([keylo_bin, "run", config, "--data", data, "--out", out, "-q"], check=True)
    with open(out / "frames.csv") as f:
        return float(np.mean([float(r["odometry_ms"]) for r in csv.DictReader(f)]))


def python_ms_per_frame(frames):
    """Mean wall time of `process_frame`, and mean stage time inside it (what the CLI's
    `frames.csv` reports as odometry_ms)."""
    odometry = keylo.Odometry(CONFIG)
    walls, stages = [], []
    for f in frames:
        t = time.perf_counter()
        r = odometry.process_frame(f)
        walls.append(time.perf_counter() - t)
        stages.append(r.timings["total"])
    return 1e3 * float(np.mean(walls)), 1e3 * float(np.mean(stages))


class Fixed:
    """A detector whose own work is nothing: it returns the same 500 keypoints."""

    def __init__(self):
        rng = np.random.default_rng(0)
        self.points = np.stack([rng.uniform(5, 1000, 500), rng.uniform(5, 58, 500)], 1).astype(np.float32)
        self.own = 0.0
        self.calls = 0

    def detect(self, image):
        t = time.perf_counter()
        out = self.points
        self.own += time.perf_counter() - t
        self.calls += 1
        return out


def detector_overhead_ms(frames):
    fixed = Fixed()
    keylo.register_detector("fixed", fixed)
    odometry = keylo.Odometry(CONFIG + '\n[image]\nkind = "lidar"\nimages = ["signal", "range"]\n'
                              '\n[detector]\nkind = "python:fixed"\n')
    detect = 0.0
    for f in frames:
        detect += odometry.process_frame(f).timings["detect"]
    return 1e3 * (detect - fixed.own) / fixed.calls


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--keylo", required=True)
    p.add_argument("--frames", type=int, default=100)
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        data = tmp / "lab"
        subprocess.run([args.keylo, "sim", "--frames", str(args.frames), "--out", data, "-q"], check=True)
        config = tmp / "c.toml"
        config.write_text(CONFIG)
        frames = list(keylo.open(data))
        cli, py, inside = [], [], []
        for k in range(args.repeats):
            cli.append(cli_ms_per_frame(args.keylo, config, data, tmp / f"out{k}"))
            wall, stages = python_ms_per_frame(frames)
            py.append(wall)
            inside.append(stages)
        c, q, s = min(cli), min(py), min(inside)
        print(f"{len(frames)} simulated OS0-128 lab frames, passthrough + KISS-ICP, best of {args.repeats}:")
        print(f"  keylo run: {c:.2f} ms/frame in the stages (frames.csv odometry_ms)")
        print(f"  Python: {s:.2f} ms/frame in the stages, {q:.2f} ms/frame wall of process_frame")
        print(f"  Python wall over the CLI's stage time: {100 * (q / c - 1):+.1f} % (target <= 5 %)")
        print(f"  of which outside the stages (Rust bookkeeping + the Python call): {q - s:.3f} ms/frame")
        d = min(detector_overhead_ms(frames[:20]) for _ in range(args.repeats))
        print(f"  Python detector call overhead: {d:.3f} ms per image (target <= 0.2 ms)")


if __name__ == "__main__":
    main()
