#!/usr/bin/env python3
"""Make the INT8 XFeat model (`xfeat_int8.onnx`) from keylo's FP32 one (`xfeat.onnx`).

Usage: quantize_xfeat.py xfeat.onnx TIERS_SIGNAL_DIR xfeat_int8.onnx
Needs: onnxruntime 1.32, onnx, numpy, opencv-python-headless (pip).

1. The model is converted from opset 12 to 13 (per-channel QDQ needs it; ONNX's converter).
2. Static QDQ quantization with ONNX Runtime (activations uint8, weights int8 per output
   channel), calibrated on images 0-99 of the TIERS signal images (1024x64, linear
   interpolation, the grey image in all three input channels, as keylo feeds it) with the
   99.99th percentile of each activation.
3. The keypoint head (the four 1x1 convolutions on the 8x8-unfolded image, to the 65 logits;
   a small share of the work) stays FP32: quantized, 94.0 % of the FP32 keypoints were found
   again within 1 px on images 100-199; kept FP32, 97.7 % (printed below). On 2 cores of
   the development machine the INT8 network took 5.4 ms per 1024x64 image against 7.1 ms.
The script prints the speed of both models and the share of FP32 keypoints found again.
"""
import sys
import tempfile
import time

import cv2
import numpy as np
import onnx
import onnxruntime as ort
from onnx import version_converter
from onnxruntime.quantization import (CalibrationDataReader, CalibrationMethod, QuantFormat,
                                      QuantType, quantize_static)
from onnxruntime.quantization.shape_inference import quant_pre_process
from scipy.ndimage import maximum_filter

CALIBRATION_IMAGES = range(0, 100)
CHECK_IMAGES = range(100, 200)


def image(folder, i):
    grey = cv2.imread(f"{folder}/image_{i:04d}.png", cv2.IMREAD_GRAYSCALE)
    grey = cv2.resize(grey, (1024, 64), interpolation=cv2.INTER_LINEAR).astype(np.float32) / 255
    return np.repeat(grey[None, None], 3, axis=1)


class Calibration(CalibrationDataReader):
    def __init__(self, folder):
        self.images = (image(folder, i) for i in CALIBRATION_IMAGES)

    def get_next(self):
        x = next(self.images, None)
        return None if x is None else {"input": x}


def keypoint_head(model):
    """The 1x1 convolutions from the unfolded image (SpaceToDepth) to the 65 logits."""
    consumers = {}
    for n in model.graph.node:
        for i in n.input:
            consumers.setdefault(i, []).append(n)
    s2d = next(n for n in model.graph.node if n.op_type == "SpaceToDepth")
    head, frontier = [], [s2d.output[0]]
    while frontier:
        t = frontier.pop()
        for n in consumers.get(t, []):
            if n.op_type == "Conv" and n.name not in head:
                head.append(n.name)
            if n.op_type in ("Conv", "Relu", "BatchNormalization", "Add"):
                frontier.extend(n.output)
    return head


def session(path):
    o = ort.SessionOptions()
    o.intra_op_num_threads = 2
    o.add_session_config_entry("session.intra_op.allow_spinning", "0")
    return ort.InferenceSession(path, o, providers=["CPUExecutionProvider"])


def peaks(out):
    logits = out[1][0]
    e = np.exp(logits - logits.max(0))
    p = (e / e.sum(0))[:64]
    hc, wc = p.shape[1:]
    heat = p.reshape(8, 8, hc, wc).transpose(2, 0, 3, 1).reshape(hc * 8, wc * 8)
    top = maximum_filter(heat, size=5, mode="constant", cval=-np.inf)
    return np.argwhere((heat == top) & (heat > 0.05))


def main(src, tiers, out):
    with tempfile.TemporaryDirectory() as tmp:
        op13, prepared = f"{tmp}/op13.onnx", f"{tmp}/prepared.onnx"
        onnx.save(version_converter.convert_version(onnx.load(src), 13), op13)
        quant_pre_process(op13, prepared, skip_symbolic_shape=True)
        head = keypoint_head(onnx.load(prepared))
        print("FP32:", head)
        quantize_static(prepared, out, Calibration(tiers), quant_format=QuantFormat.QDQ,
                        per_channel=True, activation_type=QuantType.QUInt8,
                        weight_type=QuantType.QInt8, calibrate_method=CalibrationMethod.Percentile,
                        extra_options={"CalibPercentile": 99.99}, nodes_to_exclude=head)
    a, b = session(src), session(out)
    for name, s in (("fp32", a), ("int8", b)):
        s.run(None, {"input": image(tiers, 150)})
        t = time.perf_counter()
        for i in CHECK_IMAGES:
            s.run(None, {"input": image(tiers, i)})
        print(f"{name}: {1e3 * (time.perf_counter() - t) / len(CHECK_IMAGES):.2f} ms per image")
    found = total = 0
    for i in CHECK_IMAGES:
        x = image(tiers, i)
        pa, pb = peaks(a.run(None, {"input": x})), peaks(b.run(None, {"input": x}))
        total += len(pa)
        found += sum(1 for p in pa if len(pb) and np.abs(pb - p).max(axis=1).min() <= 1)
    print(f"FP32 keypoints found again within 1 px: {found / total:.3f} ({found} of {total})")


if __name__ == "__main__":
    main(*sys.argv[1:4])
