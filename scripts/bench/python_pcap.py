"""Frame iteration over an Ouster capture from Python: keylo.open against ouster-sdk's
Python API, the same work (every channel destaggered and the XYZ points), the same XYZ.

    python scripts/bench/python_pcap.py PCAP [REPEATS]

Run with the python of ../shared/peers/setup-venv.sh after `pip install ./crates/keylo-py`
there (both packages in one interpreter). Prints ms per frame of each (interleaved passes,
the best of REPEATS), their ratio, and the largest XYZ difference over every valid pixel.
"""

import sys
import time

import numpy as np
from ouster.sdk import core, open_source

import keylo


def keylo_pass(pcap):
    xyz = []
    reader = keylo.open(pcap, partial_frames="keep")   # opening is timed apart, as for the SDK
    t = time.perf_counter()
    for f in reader:
        _ = f.range, f.signal, f.reflectivity, f.near_ir, f.valid
        xyz.append(f.xyz)
    return time.perf_counter() - t, xyz


def sdk_pass(pcap, meta):
    src = open_source(pcap, meta=[meta])
    info = src.sensor_info[0]
    lut = core.XYZLut(info)
    xyz = []
    t = time.perf_counter()
    for scans in src:
        scan = scans[0]
        if scan is None:
            continue
        _ = [core.destagger(info, scan.field(f)) for f in scan.fields if f != "FLAGS"]
        xyz.append(core.destagger(info, lut(scan.field("RANGE"))))
    return time.perf_counter() - t, xyz


def main():
    pcap = sys.argv[1]
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    meta = pcap[:-5] + ".json"
    best_k, best_s = float("inf"), float("inf")
    for _ in range(repeats):
        tk, xk = keylo_pass(pcap)
        ts, xs = sdk_pass(pcap, meta)
        best_k, best_s = min(best_k, tk), min(best_s, ts)
    assert len(xk) == len(xs), (len(xk), len(xs))
    worst = 0.0
    for a, b in zip(xk, xs):
        valid = np.linalg.norm(b, axis=2) > 0
        worst = max(worst, float(np.abs(a[valid] - b[valid]).max()))
    n = len(xk)
    k, s = 1e3 * best_k / n, 1e3 * best_s / n
    print(f"{pcap}: {n} frames, best of {repeats} passes")
    print(f"  keylo.open: {k:.2f} ms/frame; ouster-sdk: {s:.2f} ms/frame; ouster-sdk / keylo = {s / k:.2f}")
    print(f"  largest |xyz difference| over valid pixels: {worst:.2e} m")


if __name__ == "__main__":
    main()
