"""How each beam's signal gain wanders with range, on a capture with range and signal: for
every pixel whose vertical neighbours (rows ±1, ±2) lie on the same surface (range within
10 % + 5 cm), the log of the pixel over their mean; per beam and range bin, the median of it;
minus the beam's median over all ranges. Prints, per range bin, the spread (standard
deviation) of that over the beams: 0 if every beam's gain is the same at every range. Also
prints the median |log ratio| (minus each beam's median) over all such pixels and its
autocorrelation along the row (lags in columns): how strong and how long the row-to-row
streaks on one surface are.

    target/py-venv/bin/python scripts/sim/beam_range_response.py \
        ../shared/data/ouster/OS-0-128_v3.0.1_1024x10_from_osf.pcap
    # the same measurement on simulated frames (keylo sim ... --set appearance=ouster)
    target/py-venv/bin/python scripts/sim/beam_range_response.py /tmp/lab-ouster

keylo-sim's `ouster` appearance takes its range wandering from this (appearance.rs,
RANGE_WANDER). Needs the keylo Python package (docs/python.md) and numpy.
"""

import sys
import warnings

import keylo
import numpy as np

BINS = [0.0, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 10.0, 100.0]
MIN_PIXELS = 30


def log_ratios(frame):
    sig = np.asarray(frame.signal, float)
    rng = np.asarray(frame.range, float)
    ok = np.asarray(frame.valid).astype(bool) & (sig > 0)
    total = np.zeros_like(sig)
    count = np.zeros_like(sig)
    for d in (-2, -1, 1, 2):
        same = np.roll(ok, d, 0) & (np.abs(np.roll(rng, d, 0) - rng) < 0.1 * rng + 0.05)
        total += np.where(same, np.roll(sig, d, 0), 0.0)
        count += same
    good = ok & (count >= 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.log(sig / np.maximum(total / np.maximum(count, 1), 1.0))
    return np.where(good, ratio, np.nan), rng


def main():
    warnings.filterwarnings("ignore", category=RuntimeWarning)  # all-NaN rows
    ratios, ranges = zip(*(log_ratios(f) for f in keylo.open(sys.argv[1])))
    ratio = np.concatenate(ratios, axis=1)
    rng = np.concatenate(ranges, axis=1)
    beam_median = np.nanmedian(ratio, axis=1)
    streaks(ratios)
    print("range (m)   pixels  beams  spread over beams")
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        r = np.where((rng >= lo) & (rng < hi), ratio, np.nan)
        n = np.sum(~np.isnan(r), axis=1)
        med = np.array([np.nanmedian(x) if k >= MIN_PIXELS else np.nan for x, k in zip(r, n)])
        dev = med - beam_median
        beams = int(np.sum(~np.isnan(dev)))
        spread = f"{np.nanstd(dev):.3f}" if beams >= 10 else "–"
        print(f"{lo:4.1f}–{hi:<5.1f} {int(n.sum()):8d}  {beams:5d}  {spread}")


def streaks(ratios):
    amplitude, lags = [], {k: [] for k in (1, 2, 4, 8, 16, 32)}
    for r in ratios:
        r = r - np.nanmedian(r, axis=1, keepdims=True)
        amplitude.append(np.nanmedian(np.abs(r)))
        var = np.nanvar(r)
        for k, acc in lags.items():
            a, b = r[:, :-k], r[:, k:]
            both = ~np.isnan(a) & ~np.isnan(b)
            acc.append(np.mean(a[both] * b[both]) / var)
    ac = ", ".join(f"{k}: {np.mean(v):.2f}" for k, v in lags.items())
    print(f"median |log ratio| {np.mean(amplitude):.3f}; along the row, autocorrelation {ac}")


if __name__ == "__main__":
    main()
