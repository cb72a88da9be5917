"""Checks what scripts/view/live-test.sh's clients received against the runs' own files."""
import json
import math
import sys
from pathlib import Path

work, frames = Path(sys.argv[1]), int(sys.argv[2])


def tum(path):
    return [[float(v) for v in line.split()] for line in path.read_text().splitlines() if line.strip()]


def fail(message):
    sys.exit(f"[view-test] FAILED: {message}")


plain = tum(work / "plain" / "trajectory.tum")
if len(plain) != frames:
    fail(f"the run without a viewer has {len(plain)} poses, expected {frames}")
for mode in ["all", "stall", "drop"]:
    if tum(work / mode / "trajectory.tum") != plain:
        fail(f"{mode}: the trajectory differs from the run without a viewer")
    got = json.loads((work / f"{mode}.json").read_text())
    if not got["topics"]:
        fail(f"{mode}: the client received nothing")

got = json.loads((work / "all.json").read_text())
per_frame = ["/keylo/pose", "/keylo/scan", "/keylo/registered", "/keylo/stats",
             "/keylo/image/signal", "/keylo/image/signal/keypoints",
             "/keylo/image/range", "/keylo/image/range/keypoints"]
for topic in per_frame:
    if got["topics"].get(topic) != frames:
        fail(f"{topic}: {got['topics'].get(topic)} messages, expected {frames} ({got['topics']})")
if got["topics"].get("/tf") != 2 * frames:
    fail(f"/tf: {got['topics'].get('/tf')} messages, expected {2 * frames}")
for topic in ["/keylo/map", "/keylo/trajectory", "/keylo/reference"]:
    if not got["topics"].get(topic):
        fail(f"{topic}: nothing received")
# The last trajectory message (after the last frame) holds every pose, the last one the run's.
path = got.get("trajectory", {})
last = path.get("last", {})
if path.get("poses") != frames or path.get("frame_id") != "odom" or \
        any(abs(a - b) > 1e-6 for a, b in zip([last.get(k, 0) for k in "xyz"], plain[-1][1:4])):
    fail(f"the last trajectory {path} is not trajectory.tum's {frames} poses ending at {plain[-1][1:4]}")
# The reference (the simulator's ground truth) starts where the estimate starts.
ref = got.get("reference", {})
if ref.get("frame_id") != "odom" or not ref.get("poses", 0) >= frames:
    fail(f"the reference {ref}")
if got.get("map", {}).get("points", 0) <= 0 or got["map"].get("frame_id") != "odom":
    fail(f"the map {got.get('map')}")
expected_schemas = {
    "/keylo/scan": "sensor_msgs/msg/PointCloud2 [cdr]",
    "/keylo/pose": "foxglove.PoseInFrame [protobuf]",
    "/keylo/map": "foxglove.PointCloud [protobuf]",
    "/tf": "foxglove.FrameTransform [protobuf]",
    "/keylo/stats": "keylo.FrameStats [json]",
}
for topic, schema in expected_schemas.items():
    if got["schemas"].get(topic) != schema:
        fail(f"{topic}: schema {got['schemas'].get(topic)}, expected {schema}")
if [s["frame"] for s in got["stats"]] != list(range(frames)):
    fail(f"stats frames {[s['frame'] for s in got['stats']]}")
for row, pose in zip(plain, got["poses"]):
    stamp = int(pose["stamp_ns"]) / 1e9
    p, q = pose["position"], pose["orientation"]
    mine = [stamp, p["x"], p["y"], p["z"], q["x"], q["y"], q["z"], q["w"]]
    if any(abs(a - b) > 1e-6 for a, b in zip(mine, row)):
        fail(f"pose {mine} differs from trajectory.tum's {row}")
image = got["images"].get("/keylo/image/signal", {})
if (image.get("width"), image.get("height"), image.get("encoding")) != (1024, 64, "mono8"):
    fail(f"signal image {image}")
print(f"[view-test] ok: {frames} frames, {sum(got['topics'].values())} messages on "
      f"{len(got['topics'])} topics to the client; a stalled client got "
      f"{sum(json.loads((work / 'stall.json').read_text())['topics'].values())} and a dropped "
      f"one {sum(json.loads((work / 'drop.json').read_text())['topics'].values())}; "
      "every trajectory equals the run without a viewer")
