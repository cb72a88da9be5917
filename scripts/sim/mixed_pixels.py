"""Mixed pixels: the signal of a pixel beside a range jump, against its own surface further in.

For every valid pixel p whose neighbour q along a row (or a column) lies across a range jump
(|r_q - r_p| > 0.3 r_p + 0.2 m) while the two pixels on p's other side lie on p's surface
(range within 3 % + 2 cm), prints the median and quartiles of signal(p) / signal(p - 2), for
p on the nearer and on the farther side of the jump; and the same ratio inside surfaces (all
four pixels alike). Only pixels brighter than the frame's 30th percentile are counted.

    python scripts/sim/mixed_pixels.py ../shared/data/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap
    keylo sim --scene lab --frames 10 --set appearance=ouster --set speed_scale=0 \
        --set sway_scale=0 --out /tmp/lab-still
    python scripts/sim/mixed_pixels.py /tmp/lab-still

Reads with the keylo Python package (pcap, or a `keylo sim` frame folder), first 10 frames.
keylo-sim's `ouster` mixed pixels were measured with it (docs/results/sim-realism.md).
"""

import sys

import numpy as np

import keylo

JUMP_RELATIVE, JUMP_M = 0.3, 0.2
SAME_RELATIVE, SAME_M = 0.03, 0.02


def ratios(frames, axis):
    """Signal ratios at the nearer and farther side of jumps, and inside surfaces."""
    near, far, inner = [], [], []
    for f in frames:
        arrays = [np.moveaxis(np.asarray(a), axis, 1) for a in (f.range, f.signal, f.valid)]
        for flip in (False, True):
            r, s, v = (a[:, ::-1] if flip else a for a in arrays)
            r, s = r.astype(float), s.astype(float)
            p2, p1, p0, q = r[:, :-3], r[:, 1:-2], r[:, 2:-1], r[:, 3:]
            ok = v[:, :-3] & v[:, 1:-2] & v[:, 2:-1] & v[:, 3:]
            same = SAME_RELATIVE * p0 + SAME_M
            smooth = (np.abs(p0 - p1) < same) & (np.abs(p1 - p2) < same)
            jump = np.abs(q - p0) > JUMP_RELATIVE * p0 + JUMP_M
            bright = s[:, :-3] > np.percentile(s[v], 30)
            ratio = s[:, 2:-1] / np.maximum(s[:, :-3], 1)
            sel = ok & smooth & bright
            near.append(ratio[sel & jump & (q > p0)])
            far.append(ratio[sel & jump & (q < p0)])
            inner.append(ratio[sel & (np.abs(q - p0) < same)])
    return [np.concatenate(x) for x in (near, far, inner)]


def main():
    path = sys.argv[1]
    reader = keylo.open(path, partial_frames="skip-ends") if path.endswith(".pcap") else keylo.open(path)
    frames = [f for _, f in zip(range(10), reader)]
    for axis, name in ((1, "along rows"), (0, "along columns")):
        print(f"{path}, {len(frames)} frames, neighbours {name}:")
        for side, a in zip(("nearer side of a jump", "farther side of a jump", "inside a surface"),
                           ratios(frames, axis)):
            if a.size:
                q1, med, q3 = np.percentile(a, [25, 50, 75])
                print(f"  {side:24} n={a.size:7d}  median {med:.3f}  quartiles {q1:.3f} {q3:.3f}")


if __name__ == "__main__":
    main()
