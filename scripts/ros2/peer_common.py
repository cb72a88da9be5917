"""What keylo's ROS 2 peers share: Cyclone DDS set up on loopback, scans as plain dicts (from
KITTI-style .bin files or a ROS 2 bag), the two encoders (Cyclone's IDL types for DDS,
rosbags' CDR for reference bags), trajectory reading and pose helpers, and the peer itself
(a driver writing rt/points and a consumer of the node's odometry, /tf and path).
Used by interop.py, interop_control.py, live_ouster.py and scripts/bench/ros2_latency.py."""

import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))
# Cyclone DDS on loopback only (the namespace has nothing else), multicast on.
os.environ["CYCLONEDDS_URI"] = (
    '<CycloneDDS><Domain><General><Interfaces><NetworkInterface name="lo" multicast="true"/>'
    "</Interfaces></General></Domain></CycloneDDS>")

from cyclonedds.core import (  # noqa: E402
    InstanceState, Policy, Qos, ReadCondition, SampleState, ViewState, WaitSet)
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.sub import DataReader  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402
from cyclonedds.util import duration  # noqa: E402
from mcap.reader import make_reader  # noqa: E402
from mcap.writer import Writer as McapWriter  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

import ros2_idl as m  # noqa: E402

STORE = get_typestore(Stores.ROS2_HUMBLE)
FLOAT32, FLOAT64 = 7, 8
SIZES = {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 8: 8}
DTYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}
FAILURES = []


def check(ok, what):
    if not ok:
        FAILURES.append(what)
        print(f"FAIL: {what}", flush=True)
    return ok


# ---------------------------------------------------------------- scans as plain dicts

def cloud(stamp_ns, frame_id, height, width, fields, point_step, data, is_dense=True,
          row_step=None, is_bigendian=False):
    return dict(stamp_ns=stamp_ns, frame_id=frame_id, height=height, width=width,
                fields=fields, point_step=point_step,
                row_step=point_step * width if row_step is None else row_step,
                data=bytes(data), is_dense=is_dense, is_bigendian=is_bigendian)


def kitti_bins(folder, limit, t0_ns, dt_ns=100_000_000):
    folder = Path(folder)
    if (folder / "velodyne").is_dir():
        folder = folder / "velodyne"
    files = sorted(folder.glob("*.bin"))[:limit]
    out = []
    for k, f in enumerate(files):
        pts = np.fromfile(f, dtype=np.float32).reshape(-1, 4)
        fields = [("x", 0, FLOAT32, 1), ("y", 4, FLOAT32, 1), ("z", 8, FLOAT32, 1),
                  ("intensity", 12, FLOAT32, 1)]
        out.append(cloud(t0_ns + k * dt_ns, "velodyne", 1, len(pts), fields, 16, pts.tobytes()))
    return out


def bag_clouds(mcap_path, topic):
    out = []
    with open(mcap_path, "rb") as fh:
        for _schema, channel, message in make_reader(fh).iter_messages(topics=[topic]):
            c = STORE.deserialize_cdr(message.data, "sensor_msgs/msg/PointCloud2")
            stamp = c.header.stamp.sec * 1_000_000_000 + c.header.stamp.nanosec
            out.append(cloud(stamp, c.header.frame_id, c.height, c.width,
                             [(f.name, f.offset, f.datatype, f.count) for f in c.fields],
                             c.point_step, c.data.tobytes(), c.is_dense, c.row_step,
                             c.is_bigendian))
    return out


def end_stamp_ns(c):
    """The scan's end on its own clock: the stamp plus the latest time of a valid point
    (finite, not at the origin); the stamp itself without a time field."""
    names = {f[0].lower(): f for f in c["fields"]}
    tf = next((names[n] for n in ("t", "time", "timestamp") if n in names), None)
    if tf is None:
        return c["stamp_ns"], 0
    rec = records(c)
    xyz = np.stack([rec["x"], rec["y"], rec["z"]], axis=1).astype(np.float64)
    valid = np.isfinite(xyz).all(axis=1) & (np.abs(xyz).sum(axis=1) > 0)
    t = rec[tf[0]].astype(np.float64)[valid]
    t = t * (1e-9 if tf[2] not in (FLOAT32, FLOAT64) else 1.0)
    return c["stamp_ns"] + int(round(t.max() * 1e9)), 1000


def records(c):
    order = ">" if c["is_bigendian"] else "<"
    dt = np.dtype({"names": [f[0] for f in c["fields"]],
                   "formats": [order + DTYPES[f[2]] for f in c["fields"]],
                   "offsets": [f[1] for f in c["fields"]], "itemsize": c["point_step"]})
    rows = np.frombuffer(c["data"], dtype=np.uint8).reshape(c["height"], c["row_step"])
    rows = rows[:, :c["width"] * c["point_step"]].copy()
    return rows.reshape(-1).view(dt)


# ---------------------------------------------------------------- the two encoders

def to_dds(c):
    return m.PointCloud2(
        header=m.Header(stamp=m.Time(sec=c["stamp_ns"] // 10**9, nanosec=c["stamp_ns"] % 10**9),
                        frame_id=c["frame_id"]),
        height=c["height"], width=c["width"],
        fields=[m.PointField(name=n, offset=o, datatype=d, count=k) for n, o, d, k in c["fields"]],
        is_bigendian=c["is_bigendian"], point_step=c["point_step"], row_step=c["row_step"],
        data=c["data"], is_dense=c["is_dense"])


def write_reference_bag(path, clouds, topic="/points"):
    """The same clouds as a ROS 2 MCAP bag (CDR by rosbags), for `keylo run`."""
    T = STORE.types
    Header, Time, PF, PC2 = (T["std_msgs/msg/Header"], T["builtin_interfaces/msg/Time"],
                             T["sensor_msgs/msg/PointField"], T["sensor_msgs/msg/PointCloud2"])
    msgtype = "sensor_msgs/msg/PointCloud2"
    with open(path, "wb") as fh:
        w = McapWriter(fh)
        w.start(profile="ros2", library="keylo scripts/ros2/interop.py")
        msgdef, _ = STORE.generate_msgdef(msgtype, ros_version=2)
        schema = w.register_schema(msgtype, "ros2msg", msgdef.encode())
        channel = w.register_channel(topic, "cdr", schema)
        for c in clouds:
            s = c["stamp_ns"]
            msg = PC2(header=Header(stamp=Time(sec=s // 10**9, nanosec=s % 10**9),
                                    frame_id=c["frame_id"]),
                      height=c["height"], width=c["width"],
                      fields=[PF(name=n, offset=o, datatype=d, count=k)
                              for n, o, d, k in c["fields"]],
                      is_bigendian=c["is_bigendian"], point_step=c["point_step"],
                      row_step=c["row_step"], data=np.frombuffer(c["data"], dtype=np.uint8),
                      is_dense=c["is_dense"])
            w.add_message(channel, log_time=s, publish_time=s,
                          data=bytes(STORE.serialize_cdr(msg, msgtype)))
        w.finish()


def reference_run(name, keylo, clouds, out, config=None, sets=()):
    """The clouds as a ROS 2 MCAP bag in `out` and `keylo run` on it, with exact trajectory
    numbers and a saved map (`out/keylo-run-map`): its poses as TUM rows, or None when it
    failed (the failure is recorded)."""
    bag = out / "reference.mcap"
    write_reference_bag(bag, clouds)
    cfg = [str(config)] if config else []
    overrides = sum((["--set", s] for s in ("output.exact=true",) + tuple(sets)), [])
    r = subprocess.run([keylo, "-q", "run"] + cfg + ["--data", str(bag), "--out", str(out / "keylo-run"),
                        "--prefetch", "0", "--map-out", str(out / "keylo-run-map")] + overrides,
                       capture_output=True, text=True)
    if not check(r.returncode == 0, f"{name}: keylo run on the reference bag: {r.stderr[-2000:]}"):
        return None
    return read_tum(out / "keylo-run/trajectory.tum")


def finish():
    """Ends a peer script: exit status 1 when a check failed."""
    if FAILURES:
        print(f"{len(FAILURES)} check(s) failed", flush=True)
        sys.exit(1)
    print("all checks passed", flush=True)


def read_map_ply(path):
    """The points of a keylo map's binary PLY (x, y, z, intensity float32) as an N×4 array."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    return np.frombuffer(data[end:], dtype="<f4").reshape(-1, 4)


def read_tum(path):
    rows = [list(map(float, line.split())) for line in Path(path).read_text().splitlines()
            if line.strip() and not line.startswith("#")]
    return np.array(rows).reshape(-1, 8)


def quat_angle(q1, q2):
    d = abs(float(np.dot(q1, q2)))
    return 2.0 * math.acos(min(1.0, d))


# ---------------------------------------------------------------- one stream

class Peer:
    def __init__(self, domain):
        self.dp = DomainParticipant(domain)
        self.rel = rel = Qos(Policy.Reliability.Reliable(duration(seconds=1)),
                             Policy.History.KeepLast(100), Policy.Durability.Volatile)
        self.points = DataWriter(self.dp, Topic(self.dp, "rt/points", m.PointCloud2), qos=rel)
        self.odom = DataReader(self.dp, Topic(self.dp, "rt/keylo/odometry", m.Odometry), qos=rel)
        self.tf = DataReader(self.dp, Topic(self.dp, "rt/tf", m.TFMessage), qos=rel)
        self.path = DataReader(self.dp, Topic(self.dp, "rt/keylo/path", m.Path), qos=rel)
        self.waitset = None

    def wait_matched(self, timeout=30.0):
        t0 = time.time()
        while time.time() - t0 < timeout:
            if (self.points.get_publication_matched_status().current_count > 0
                    and self.odom.get_subscription_matched_status().current_count > 0):
                return True
            time.sleep(0.05)
        return False

    def answer(self, timeout):
        """The next odometry message, waiting on a Cyclone wait set (no polling, so the peer
        takes no CPU from the node while it waits); Cyclone's markers of a writer gone
        (InvalidSample, when the node ends) are not messages."""
        if self.waitset is None:
            self.waitset = WaitSet(self.dp)
            mask = SampleState.NotRead | ViewState.Any | InstanceState.Any
            self.waitset.attach(ReadCondition(self.odom, mask))
        end = time.time() + timeout
        while True:
            got = [s for s in self.odom.take(N=1) if isinstance(s, m.Odometry)]
            if got:
                return got[0], time.time()
            left = end - time.time()
            if left <= 0:
                return None, time.time()
            self.waitset.wait(duration(seconds=min(left, 1.0)))


def pose_matrix(t, q):
    x, y, z, w = q
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m_ = np.eye(4)
    m_[:3, :3], m_[:3, 3] = r, t
    return m_


def msg_matrix(p):
    return pose_matrix([p.position.x, p.position.y, p.position.z],
                       [p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w])


