"""keylo's XFeat model: the upstream ONNX export of XFeat (verlab/accelerated_features,
Apache-2.0, `weights/xfeat.onnx` at commit c58e74fc86c0e1f9038e0fb8807de59d27dd30d5, the
authors' export of their released weights) made size-agnostic, so one model serves 1024x64
LiDAR images and any other size (height and width multiples of 32).

The upstream export is fixed to 640x640 inputs in two places, both rewritten here, nothing else:
1. The two bilinear resizes of the coarse feature maps to the 1/8 map (`F.interpolate` to
   x3's size) carry a constant output size (80, 80): it becomes x3's own spatial shape.
2. The keypoint head's 8x8 unfold of the normalised image was exported as 160 slices and a
   reshape to (80, 80): it becomes the one op it is, SpaceToDepth(8) (channel = 8 row + col
   in the block, as the unfold orders them).
The result is checked against the upstream model on random 640x640 inputs (outputs within
1e-5) before it is written.

  python3 -m venv V && V/bin/pip install onnx onnxruntime numpy
  git -C <accelerated_features clone> show c58e74fc86c0e1f9038e0fb8807de59d27dd30d5:weights/xfeat.onnx > xfeat_upstream.onnx
  V/bin/python crates/keylo-features/models/xfeat/make_xfeat_onnx.py xfeat_upstream.onnx crates/keylo-features/models/xfeat/xfeat.onnx
"""
import hashlib
import sys

import numpy as np
import onnx
import onnxruntime as ort
from onnx import helper, numpy_helper

UPSTREAM_SHA256 = "54041f61f0d9b1968451a65fe0fd79e96692b1d8266c54a6939a73e847df5988"


def main(src, dst):
    data = open(src, "rb").read()
    if hashlib.sha256(data).hexdigest() != UPSTREAM_SHA256:
        sys.exit(f"{src} is not the upstream xfeat.onnx of commit c58e74f")
    m = onnx.load_from_string(data)
    g = m.graph
    nodes = list(g.node)
    by_out = {o: n for n in nodes for o in n.output}
    by_name = {n.name: n for n in nodes}

    # 1. Resize sizes: concat(shape(x)[:2], shape(x3)[2:4]), x3 the other operand of the Add
    #    the resized maps are summed into.
    resizes = [n for n in nodes if n.op_type == "Resize"]
    assert len(resizes) == 2, "expected the two coarse-map resizes"
    consumers = {}
    for n in nodes:
        for i in n.input:
            consumers.setdefault(i, []).append(n)
    add = next(n for n in consumers[resizes[0].output[0]] if n.op_type == "Add")
    x3 = next(i for i in add.input if i != resizes[0].output[0])
    new_nodes = [
        helper.make_node("Shape", [x3], ["keylo_x3_shape"], name="keylo_x3_shape"),
        helper.make_node("Constant", [], ["keylo_2"], name="keylo_2", value=numpy_helper.from_array(np.array([2], np.int64))),
        helper.make_node("Constant", [], ["keylo_4"], name="keylo_4", value=numpy_helper.from_array(np.array([4], np.int64))),
        helper.make_node("Constant", [], ["keylo_0"], name="keylo_0", value=numpy_helper.from_array(np.array([0], np.int64))),
        helper.make_node("Slice", ["keylo_x3_shape", "keylo_2", "keylo_4", "keylo_0"], ["keylo_x3_hw"],
                         name="keylo_x3_hw"),
    ]
    for r in resizes:
        concat = by_out[r.input[3]]
        assert concat.op_type == "Concat" and len(concat.input) == 2
        fixed = next(i for i in g.initializer if i.name == concat.input[1])
        assert numpy_helper.to_array(fixed).tolist() == [80, 80], "unexpected resize size"
        concat.input[1] = "keylo_x3_hw"

    # 2. The unfold: everything from the normalised image to the second reshape becomes
    #    SpaceToDepth(8).
    reshape_out = by_name["Reshape_1036"]
    assert [numpy_helper.to_array(i).tolist() for i in g.initializer if i.name == reshape_out.input[1]] == [[1, -1, 80, 80]]
    # The unfold's source: the normalised one-channel image (InstanceNormalization's output,
    # which also feeds the backbone).
    norm = [n for n in nodes if n.op_type == "InstanceNormalization"]
    assert len(norm) == 1
    image = norm[0].output[0]
    s2d = helper.make_node("SpaceToDepth", [image], [reshape_out.output[0]], blocksize=8,
                           name="keylo_unfold8")
    # The reshape's output now comes from SpaceToDepth; every node no output needs any more
    # (the 640-specific slices) is dropped.
    kept = [n for n in nodes if n is not reshape_out]
    first_use = min(i for i, n in enumerate(kept) if reshape_out.output[0] in n.input)
    kept.insert(first_use, s2d)
    first_resize = min(i for i, n in enumerate(kept) if n.op_type == "Concat" and "keylo_x3_hw" in n.input)
    for k, n in enumerate(new_nodes):
        kept.insert(first_resize + k, n)
    producer = {o: n for n in kept for o in n.output}
    needed, stack = set(), [o.name for o in g.output]
    while stack:
        t = stack.pop()
        n = producer.get(t)
        if n is None or n.name in needed:
            continue
        needed.add(n.name)
        stack.extend(n.input)
    kept = [n for n in kept if n.name in needed]
    del g.node[:]
    g.node.extend(kept)
    used = {i for n in g.node for i in n.input}
    keep_init = [i for i in g.initializer if i.name in used]
    del g.initializer[:]
    g.initializer.extend(keep_init)
    del g.value_info[:]
    d = g.input[0].type.tensor_type.shape.dim
    d[2].dim_param, d[3].dim_param = "height", "width"
    for o in g.output:
        od = o.type.tensor_type.shape.dim
        od[2].dim_param, od[3].dim_param = "height_8", "width_8"
    onnx.checker.check_model(m)
    out = m.SerializeToString()

    # Check: the same outputs as upstream on 640x640, and shapes on LiDAR sizes.
    a = ort.InferenceSession(data, providers=["CPUExecutionProvider"])
    b = ort.InferenceSession(out, providers=["CPUExecutionProvider"])
    rng = np.random.default_rng(0)
    for _ in range(3):
        x = rng.random((1, 3, 640, 640), np.float32)
        for ya, yb in zip(a.run(None, {"input": x}), b.run(None, {"input": x})):
            err = float(np.abs(ya - yb).max())
            if err > 1e-5:
                sys.exit(f"rewritten model differs from upstream by {err}")
    for h, w in [(64, 1024), (128, 2048), (480, 640)]:
        shapes = [y.shape for y in b.run(None, {"input": rng.random((1, 3, h, w), np.float32)})]
        assert shapes == [(1, 64, h // 8, w // 8), (1, 65, h // 8, w // 8), (1, 1, h // 8, w // 8)], shapes
    open(dst, "wb").write(out)
    print(f"wrote {dst}: {len(g.node)} nodes (upstream {len(nodes)}), "
          f"sha256 {hashlib.sha256(out).hexdigest()}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
