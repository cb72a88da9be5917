"""Golden XFeat keypoints, scores and descriptors for crates/keylo-features/tests/xfeat.rs,
from the authors' own numpy post-processing: `infer.py` of verlab/accelerated_features at
commit c58e74fc86c0e1f9038e0fb8807de59d27dd30d5 (Apache-2.0), imported unmodified from a
checkout, run on keylo's model (xfeat.onnx beside this script) through onnxruntime.
Two things are set around it: `torch` is stubbed (infer.py imports it but its numpy path
does not use it), and its `preprocess`, which resizes every image to the upstream model's fixed
640x640, passes the 1024x64 image through (keylo's model takes any size). Its bicubic
descriptor sampling uses a = -0.5 where XFeat's PyTorch code (F.grid_sample) uses -0.75, so
descriptors are compared by cosine, keypoints and scores exactly.

Input: tests/fixtures/kpeval/images/os0/frame000000_signal.png resized to 1024x64 (linear).

  V/bin/pip install onnxruntime numpy scipy opencv-python-headless
  V/bin/python crates/keylo-features/models/xfeat/make_golden.py ACCELERATED_FEATURES_CHECKOUT
"""
import json
import os
import subprocess
import sys
import types

import cv2
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..", "..")
COMMIT = "c58e74fc86c0e1f9038e0fb8807de59d27dd30d5"


def stub_torch():
    torch = types.ModuleType("torch")
    nn = types.ModuleType("torch.nn")
    nn.Module = object
    torch.nn = nn
    torch.inference_mode = lambda: (lambda f: f)
    sys.modules.update({"torch": torch, "torch.nn": nn})
    model = types.ModuleType("modules.model")
    model.np, model.nn, model.torch = np, nn, torch
    sys.modules.update({"modules": types.ModuleType("modules"), "modules.model": model})


def main(checkout):
    source = subprocess.run(["git", "-C", checkout, "show", f"{COMMIT}:infer.py"],
                            check=True, capture_output=True, text=True).stdout
    stub_torch()
    infer = types.ModuleType("xfeat_infer")
    infer.__file__ = os.path.join(checkout, "infer.py")
    exec(compile(source, "infer.py", "exec"), infer.__dict__)
    infer.preprocess = lambda x: (x.transpose((2, 0, 1))[None], 1.0, 1.0, 1, x.shape[0], x.shape[1])
    xf = object.__new__(infer.XFeat)
    xf.net = infer.infer_onnx(os.path.join(HERE, "xfeat.onnx"))
    xf.top_k = 4096
    xf.interpolator = infer.InterpolateSparse2d("bicubic")
    xf._nearest = infer.InterpolateSparse2d("nearest")
    xf._bilinear = infer.InterpolateSparse2d("bilinear")
    path = os.path.join(ROOT, "tests/fixtures/kpeval/images/os0/frame000000_signal.png")
    grey = cv2.resize(cv2.imread(path, cv2.IMREAD_GRAYSCALE), (1024, 64), interpolation=cv2.INTER_LINEAR)
    out = xf.detectAndCompute(np.repeat(grey[:, :, None], 3, axis=2).astype(np.float32))[0]
    golden = {
        "source": f"verlab/accelerated_features infer.py at {COMMIT}",
        "image": "tests/fixtures/kpeval/images/os0/frame000000_signal.png at 1024x64",
        "keypoints": out["keypoints"].astype(int).tolist(),
        "scores": [float(s) for s in out["scores"]],
        "descriptors": [[round(float(v), 6) for v in d] for d in out["descriptors"][:50]],
    }
    dst = os.path.join(ROOT, "tests/fixtures/xfeat/golden.json")
    with open(dst, "w") as f:
        json.dump(golden, f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {dst}: {len(golden['keypoints'])} keypoints")


if __name__ == "__main__":
    main(sys.argv[1])
