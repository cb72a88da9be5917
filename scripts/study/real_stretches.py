#!/usr/bin/env python3
"""How the real TIERS recording compares with itself under the realism goal's tests.

Reads the paper authors' per-image results (../shared/paper/per-image/COMBO.csv: row k is
image k, its keypoint count and its match metrics against image k-1) for the seven detectors
of `keylo sim realism`, cuts the recording into stretches of 100 images, and prints as
Markdown:

1. per stretch, the median [q1, q3] of each detector's count, and the median match ratio and
   match score;
2. for every two stretches X and Y, the goal's three tests applied to X's medians against Y's
   quartiles: counts of X inside Y's interquartile range, match ratio and match score within
   0.1 of Y's median (detectors of 7);
3. per detector, the counts common to the interquartile ranges of the stretches
   `keylo sim realism` reports on (moving and still apart): where there are none, no one
   simulated median can be inside all of their ranges.

A stretch of the same recording is the best "simulator" of another there can be; where it
fails the tests, no simulator tuned on one stretch can be held to them on the other.

    python3 scripts/study/real_stretches.py [--per-image DIR] > stretches.md

Standard library only; quartiles as keylo's (linear between order statistics).
"""
import argparse
import csv
import math
import os
import sys

COMBOS = "AKAZE_AKAZE ORB_ORB FAST_BRISK SHITOMASI_BRISK HARRIS_BRISK SIFT_SIFT BRISK_BRISK".split()
# (first, last) image numbers; the last still stretch is the recording's last 99 rows.
STRETCHES = [(1, 99)] + [(a, a + 99) for a in range(100, 1000, 100)] + [(1046, 1144)]
STILL = {(1, 99): "still (0–49), then slow", (1046, 1144): "still"}
# The stretches docs/results/sim-realism.md reports `keylo sim realism` on.
REPORTED = {
    "moving": [(200, 299), (300, 398), (400, 499), (500, 598), (700, 798)],
    "still": [(1, 99), (1046, 1144)],
}


def quartiles(values):
    v = sorted(x for x in values if math.isfinite(x))
    if not v:
        return None

    def at(q):
        pos = q * (len(v) - 1)
        lo, hi = math.floor(pos), math.ceil(pos)
        return v[lo] + (v[hi] - v[lo]) * (pos - lo)

    return at(0.25), at(0.5), at(0.75)


def load(directory):
    data = {}
    for combo in COMBOS:
        path = os.path.join(directory, combo + ".csv")
        try:
            with open(path, newline="") as f:
                data[combo] = {int(r["image_number"]): r for r in csv.DictReader(f)}
        except (OSError, KeyError, ValueError) as e:
            sys.exit(f"{path}: expected the authors' per-image CSV (image_number, evaluation_1 … 6): {e}")
    return data


def stats(data, combo, stretch, column):
    first, last = stretch
    rows = data[combo]
    return quartiles(float(rows[k][column]) for k in range(first, last + 1) if k in rows)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    default = os.path.normpath(os.path.join(here, "..", "..", "..", "shared", "paper", "per-image"))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-image", default=default, help="folder of the authors' per-image CSVs")
    args = ap.parse_args()
    data = load(args.per_image)
    names = [c.split("_")[0] for c in COMBOS]
    print("## Counts per stretch: median [q1, q3]\n")
    print("| images | sensor | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 2) + "|")
    for s in STRETCHES:
        cells = []
        for c in COMBOS:
            q1, m, q3 = stats(data, c, s, "evaluation_1")
            cells.append(f"{m:.0f} [{q1:.0f}, {q3:.0f}]")
        print(f"| {s[0]}–{s[1]} | {STILL.get(s, 'moving')} | " + " | ".join(cells) + " |")
    print("\n## Match ratio / match score per stretch (medians)\n")
    print("| images | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")
    for s in STRETCHES:
        cells = [
            f"{stats(data, c, s, 'evaluation_4')[1]:.2f} / {stats(data, c, s, 'evaluation_5')[1]:.2f}"
            for c in COMBOS
        ]
        print(f"| {s[0]}–{s[1]} | " + " | ".join(cells) + " |")
    print(
        "\n## Stretch against stretch: the goal's tests\n\n"
        "Row X, column Y: of 7 detectors, how many have X's median count inside Y's "
        "interquartile range / X's median match ratio within 0.1 of Y's / the same for match "
        "score.\n"
    )
    print("| X \\ Y | " + " | ".join(f"{a}–{b}" for a, b in STRETCHES) + " |")
    print("|---" * (len(STRETCHES) + 1) + "|")
    for x in STRETCHES:
        cells = []
        for y in STRETCHES:
            n = r = sc = 0
            for c in COMBOS:
                _, mx, _ = stats(data, c, x, "evaluation_1")
                q1, _, q3 = stats(data, c, y, "evaluation_1")
                n += q1 <= mx <= q3
                r += abs(stats(data, c, x, "evaluation_4")[1] - stats(data, c, y, "evaluation_4")[1]) <= 0.1
                sc += abs(stats(data, c, x, "evaluation_5")[1] - stats(data, c, y, "evaluation_5")[1]) <= 0.1
            cells.append(f"{n}/{r}/{sc}")
        print(f"| {x[0]}–{x[1]} | " + " | ".join(cells) + " |")
    print(
        "\n## Counts common to the reported stretches' interquartile ranges\n\n"
        "Per detector, the largest q1 and smallest q3 over the stretches; none where the "
        "first exceeds the second.\n"
    )
    print("| stretches | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")
    for kind, stretches in REPORTED.items():
        cells = []
        for c in COMBOS:
            ranges = [stats(data, c, s, "evaluation_1") for s in stretches]
            lo, hi = max(r[0] for r in ranges), min(r[2] for r in ranges)
            cells.append(f"{lo:.0f}–{hi:.0f}" if lo <= hi else f"none ({lo:.0f} > {hi:.0f})")
        label = ", ".join(f"{a}–{b}" for a, b in stretches)
        print(f"| {kind}: {label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
