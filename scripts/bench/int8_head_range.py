#!/usr/bin/env python3
"""INT8 SuperPoint against FP32, per group of images: keypoints, the share of FP32's found
again within 1 px, and how often each INT8 model clips the detector head's activations
(docs/results/realtime.md, "The detector head's range"; crates/keylo-features/models/
quantize_superpoint.py, step 3).

Usage: int8_head_range.py FP32.onnx INT8.onnx [INT8.onnx ...] -- NAME=GLOB[@GAMMA] ...

Each group is a glob of 8-bit PNG images (any size; resized to 1024x64 with linear
interpolation and fed to both input channels, as keylo does). @GAMMA applies a gamma to the
8-bit image first (0.5 for range images, as the paper's configs do). Keypoints are decoded as
the paper's settings have it (confidence 0.015, NMS radius 4, border 4), in NumPy: counts can
differ from keylo's by a keypoint now and then. Needs onnxruntime, onnx, numpy, scipy, opencv.
"""
import glob
import pathlib
import sys

import numpy as np
import onnx
import onnxruntime as ort
from onnx import numpy_helper
from scipy.ndimage import maximum_filter
from scipy.spatial import cKDTree

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "crates/keylo-features/models"))
import quantize_superpoint as q  # noqa: E402


def session(model):
    opts = ort.SessionOptions()
    opts.intra_op_num_threads = 2
    return ort.InferenceSession(model, opts, providers=["CPUExecutionProvider"])


def keypoints(sess, x, conf=0.015, radius=4, border=4):
    logits = sess.run(["scores"], {"image": x})[0][0]
    e = np.exp(logits - logits.max(0))
    p = (e / e.sum(0))[:64]
    hc, wc = p.shape[1:]
    heat = p.reshape(8, 8, hc, wc).transpose(2, 0, 3, 1).reshape(hc * 8, wc * 8)
    keep = (heat >= conf) & (heat == maximum_filter(heat, size=2 * radius + 1))
    keep[:border], keep[-border:], keep[:, :border], keep[:, -border:] = 0, 0, 0, 0
    return np.argwhere(keep)


def head_ranges(int8_model):
    """The (low, high) range each HEAD_TENSOR is quantized to in an INT8 model."""
    m = onnx.load(int8_model)
    init = {i.name: numpy_helper.to_array(i) for i in m.graph.initializer}
    out = {}
    for n in m.graph.node:
        if n.op_type == "QuantizeLinear" and n.input[0] in q.HEAD_TENSORS:
            s, z = float(init[n.input[1]]), int(init[n.input[2]])
            out[n.input[0]] = (-s * z, s * (255 - z))
    return out


def main(argv):
    if "--" not in argv or argv.index("--") < 2:
        raise SystemExit(__doc__)
    models, groups = argv[: argv.index("--")], argv[argv.index("--") + 1:]
    fp32, int8s = session(models[0]), models[1:]
    sessions = [session(m) for m in int8s]
    ranges = [head_ranges(m) for m in int8s]
    # The FP32 model with its BatchNorms rewritten as the quantizer does, so that the head's
    # tensors are the ones the INT8 models quantize.
    head = q.session_with_outputs(q.batchnorm_to_add(onnx.load(models[0])), q.HEAD_TENSORS)
    relu = q.HEAD_TENSORS[0]
    print("group | images | FP32 keypoints | per INT8 model: keypoints, FP32's within 1 px, "
          "head ReLU values clipped (per 10 000), largest / range")
    for g in groups:
        name, _, spec = g.partition("=")
        pattern, _, gamma = spec.partition("@")
        files = sorted(glob.glob(pattern))
        if not files:
            raise SystemExit(f"{name}: no file matches {pattern}")
        gamma = float(gamma) if gamma else 1.0
        n32, n8, hit = 0, [0] * len(int8s), [0] * len(int8s)
        clipped, size, largest = [0] * len(int8s), 0, 0.0
        for f in files:
            x = q.image(f, gamma)
            a = keypoints(fp32, x)
            n32 += len(a)
            v = head.run([relu], {"image": x})[0]
            size += v.size
            largest = max(largest, float(v.max()))
            for i, s in enumerate(sessions):
                b = keypoints(s, x)
                n8[i] += len(b)
                if len(a) and len(b):
                    hit[i] += int((cKDTree(b).query(a)[0] <= 1.0).sum())
                clipped[i] += int((v > ranges[i][relu][1]).sum())
        cols = [f"{n8[i]}, {100 * hit[i] / max(n32, 1):.0f} %, {1e4 * clipped[i] / size:.1f}, "
                f"{largest / ranges[i][relu][1]:.1f}" for i in range(len(int8s))]
        print(f"{name} | {len(files)} | {n32} | " + " | ".join(cols), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
