#!/usr/bin/env python3
"""SuperPoint network time with ONNX Runtime's Python API on the raw images that
`superpoint_timing` wrote, for scripts/bench/superpoint_timing.sh.
Usage: superpoint_python_timing.py MODEL.onnx IMAGE_DIR REPEATS THREADS
Prints one JSON object: milliseconds per image (inference only: input scaling and padding
are done once outside the timed loop, so this is a lower bound for a full detector)."""
import glob
import json
import os
import sys
import time

import numpy as np
import onnxruntime as ort


def main(model, image_dir, repeats, threads):
    repeats, threads = int(repeats), int(threads)
    opts = ort.SessionOptions()
    opts.intra_op_num_threads = threads
    sess = ort.InferenceSession(model, opts, providers=["CPUExecutionProvider"])
    name = sess.get_inputs()[0].name
    channels = sess.get_inputs()[0].shape[1]
    ms = {}
    for path in sorted(glob.glob(os.path.join(image_dir, "*.u8"))):
        kind, dims = os.path.basename(path)[4:-3].rsplit("_", 1)
        w, h, planes = (int(v) for v in dims.split("x"))
        img = np.fromfile(path, np.uint8).reshape(h, w, planes)
        x = np.zeros((1, channels, -(-h // 8) * 8, -(-w // 8) * 8), np.float32)
        for c in range(channels):
            x[0, c, :h, :w] = img[:, :, min(c, planes - 1)] / np.float32(255.0)
        sess.run(None, {name: x})
        start = time.perf_counter()
        for _ in range(repeats):
            sess.run(None, {name: x})
        ms.setdefault(kind, []).append((time.perf_counter() - start) * 1e3 / repeats)
    print(json.dumps({"tool": f"onnxruntime {ort.__version__} (Python)", "threads": threads,
                      "per_image": {k: {"ms": sum(v) / len(v)} for k, v in ms.items()}}))


if __name__ == "__main__":
    main(*sys.argv[1:5])
