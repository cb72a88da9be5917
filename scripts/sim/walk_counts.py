#!/usr/bin/env python3
"""The `ouster` lab's keypoint counts along its whole walk against the whole real recording's.

The lab's clutter was tuned with this measurement (docs/results/sim-realism.md, thirteenth
session): `keylo sim realism` on still views from four places of the loop (laps 0, 1/8, 1/4
and 3/8; by the loop's symmetry the rest of it looks alike), each with its own layouts, and
the mean of the four simulated medians per detector against the median count of the real
images of the authors' per-image results (../shared/paper/per-image, images 1–1144). Prints a
Markdown table: per lap and their mean, the real median, and the score the search minimised
(the sum over detectors of |log(simulated / real)|).

The target leaves out the stretches `keylo sim realism` reports on (`--hold-out`, default
1-99,200-299,300-398,400-499,500-598,700-798,1046-1144: 449 images are left), so the lab
is tuned on some images and reported on others; `--hold-out none` takes every image (the
target the search itself used, which differs by 0–5 keypoints per detector).

    python3 scripts/sim/walk_counts.py [--keylo target/release/keylo] [--seeds 6]
        [--seed 200] [--per-image ../shared/paper/per-image] [--real ../shared/data/tiers_signal]
        [--hold-out 1-99,200-299,...|none]

`--real` only feeds `keylo sim realism` its real half (12 images, not used here). Standard
library only (the per-image CSVs are read with scripts/study/real_stretches.py); about 40 s
with 6 seeds on the 2-core machine.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "study"))
from real_stretches import COMBOS, REPORTED, load  # noqa: E402

LAPS = [0.0, 0.125, 0.25, 0.375]

# The stretches `keylo sim realism` is reported on (docs/results/sim-realism.md).
HOLD_OUT = ",".join(f"{a}-{b}" for a, b in sorted(r for rs in REPORTED.values() for r in rs))


def parse_hold_out(text):
    """`A-B,C-D,…` (inclusive image numbers) or `none`."""
    if text == "none":
        return []
    out = []
    for part in text.split(","):
        try:
            a, b = (int(x) for x in part.split("-"))
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected A-B,C-D,… or none, got {part!r}")
        if a > b:
            raise argparse.ArgumentTypeError(f"{part!r} ends before it starts")
        out.append((a, b))
    return out


def real_medians(directory, hold_out):
    data = load(directory)
    out = []
    for combo in COMBOS:
        path = os.path.join(directory, combo + ".csv")
        try:
            kept = [float(r["evaluation_1"]) for k, r in data[combo].items()
                    if not any(a <= k <= b for a, b in hold_out)]
        except (KeyError, ValueError) as e:
            sys.exit(f"{path}: expected the authors' per-image CSV (image_number, evaluation_1 …): {e}")
        if not kept:
            sys.exit(f"{path}: --hold-out leaves no image")
        out.append(statistics.median(kept))
    return out, len(kept)


def lab_medians(keylo, real, lap, seed, seeds, out):
    cmd = [keylo, "sim", "realism", "--real", real, "--real-frames", "12", "--frames", "2",
           "--seeds", str(seeds), "--set", "columns=2048", "--set", f"start_lap={lap}",
           "--set", f"seed={seed}", "--channels", "signal", "--out", out, "-q"]
    subprocess.run(cmd, check=True)
    with open(os.path.join(out, "realism.json")) as f:
        sets = json.load(f)["sets"]
    sim = next(s for s in sets if s["name"] == "sim signal")
    by_combo = {c["combo"]: dict(c["metrics"])["keypoints"]["median"] for c in sim["combos"]}
    return [by_combo[c] for c in COMBOS]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.join(here, "..", "..")
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--keylo", default=os.path.join(root, "target", "release", "keylo"))
    p.add_argument("--seeds", type=int, default=6)
    p.add_argument("--seed", type=int, default=200)
    p.add_argument("--per-image", default=os.path.join(root, "..", "shared", "paper", "per-image"))
    p.add_argument("--real", default=os.path.join(root, "..", "shared", "data", "tiers_signal"))
    p.add_argument("--hold-out", type=parse_hold_out, default=parse_hold_out(HOLD_OUT))
    a = p.parse_args()
    real, kept = real_medians(a.per_image, a.hold_out)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, lap in enumerate(LAPS):
            seed = a.seed + i * a.seeds
            rows.append(lab_medians(a.keylo, a.real, lap, seed, a.seeds, os.path.join(tmp, str(i))))
    mean = [statistics.mean(r[j] for r in rows) for j in range(len(COMBOS))]
    score = sum(abs(math.log(m / t)) for m, t in zip(mean, real))
    names = [c.split("_")[0] for c in COMBOS]
    print("| | " + " | ".join(names) + " |")
    print("|---" * (len(COMBOS) + 1) + "|")
    for lap, r in zip(LAPS, rows):
        print(f"| lab, lap {lap:g} | " + " | ".join(f"{x:.0f}" for x in r) + " |")
    print("| lab, mean of the four | " + " | ".join(f"{x:.0f}" for x in mean) + " |")
    held = ", ".join(f"{x}–{y}" for x, y in a.hold_out) or "none"
    print(f"| real, images 1–1144 less {held} ({kept} images) | " + " | ".join(f"{x:.0f}" for x in real) + " |")
    print(f"\nscore (sum of |log(lab / real)|): {score:.3f}")


if __name__ == "__main__":
    main()
