"""Times ouster-sdk reading an Ouster capture into destaggered channels and XYZ, the same
work keylo's `ouster_decode_timing` example does; prints milliseconds per frame as JSON.
Opening the source and making the XYZ table (per sensor, not per frame) are timed apart.

Usage: python ouster_sdk_timing.py PCAP [REPEATS]   (python of ../shared/peers/setup-venv.sh)
"""
import json, sys, time

from ouster.sdk import core, open_source

pcap = sys.argv[1]
repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 20
meta = pcap[:-5] + ".json"
frames, checksum = 0, 0.0
open_s, frames_s = 0.0, 0.0
for _ in range(repeats):
    t = time.perf_counter()
    src = open_source(pcap, meta=[meta])
    info = src.sensor_info[0]
    lut = core.XYZLut(info)
    open_s += time.perf_counter() - t
    t = time.perf_counter()
    for scans in src:
        scan = scans[0]
        if scan is None:
            continue
        channels = [core.destagger(info, scan.field(f)) for f in scan.fields if f != "FLAGS"]
        xyz = core.destagger(info, lut(scan.field("RANGE")))
        checksum += float(xyz.reshape(-1, 3)[xyz.shape[0] * xyz.shape[1] // 2, 0])
        frames += 1
    frames_s += time.perf_counter() - t
ms = frames_s * 1e3 / max(frames, 1)
print(json.dumps({"tool": "ouster-sdk", "frames": frames, "ms_per_frame": round(ms, 3),
                  "open_ms": round(open_s * 1e3 / repeats, 3), "checksum": round(checksum, 3)}))
