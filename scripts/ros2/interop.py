"""keylo's ROS 2 node against an independent DDS implementation (Eclipse Cyclone DDS, PyPI
`cyclonedds`), run inside a private network namespace (scripts/ros2/netns.sh).

For each stream of real or simulated scans this peer, in its own process:
  1. writes the scans as a ROS 2 bag (MCAP, CDR by `rosbags`) and runs `keylo run` on it: the
     reference trajectory;
  2. starts `keylo ros2` and acts as the LiDAR driver (publishes `rt/points`, type
     `sensor_msgs::msg::dds_::PointCloud2_`) and as the consumer (`rt/keylo/odometry`,
     `rt/tf`, `rt/keylo/path`);
  3. checks that every scan is answered, with the pose of `keylo run` (<= 1e-6 m, 1e-6 rad),
     the scan's own end stamp, the frames, a symmetric positive covariance, and the TF and
     path consistent with it;
  4. midway sends bad clouds (no x field, point_step 0, point_step smaller than the fields,
     data too short, every point NaN, time going backwards, another frame_id): none is
     answered, each is logged naming the topic and the fault, and the next good scan is;
  5. stops the node with SIGINT: exit 0, its trajectory and summary complete.

  python interop.py --keylo target/debug/keylo --work DIR [--kitti DIR] [--sim-frames N]
"""

import argparse
import json
import math
import os
import signal
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


def read_tum(path):
    rows = [list(map(float, line.split())) for line in Path(path).read_text().splitlines()
            if line.strip() and not line.startswith("#")]
    return np.array(rows).reshape(-1, 8)


def quat_angle(q1, q2):
    d = abs(float(np.dot(q1, q2)))
    return 2.0 * math.acos(min(1.0, d))


# ---------------------------------------------------------------- bad clouds

def bad_clouds(good, t_back_ns):
    """Each fault once, from a good cloud (stamps after it unless the fault is the stamp)."""
    after = good["stamp_ns"] + 1_000
    out = []
    fields = [(("q" if f[0] == "x" else f[0]),) + tuple(f[1:]) for f in good["fields"]]
    out.append(("no `x` field", dict(good, stamp_ns=after, fields=fields)))
    out.append(("point_step is 0", dict(good, stamp_ns=after + 1, point_step=0)))
    out.append(("lies outside point_step", dict(good, stamp_ns=after + 2, point_step=4,
                                                row_step=4 * good["width"],
                                                data=good["data"][:4 * good["width"] * good["height"]])))
    out.append(("data holds", dict(good, stamp_ns=after + 3, data=good["data"][: len(good["data"]) // 2])))
    rec = records(good).copy()
    for axis in "xyz":
        rec[axis] = np.nan
    nan = dict(good, stamp_ns=after + 4, data=rec.tobytes(), row_step=good["point_step"] * good["width"])
    out.append(("is finite", nan))
    out.append(("not after the previous frame", dict(good, stamp_ns=t_back_ns)))
    out.append(("frame_id changed", dict(good, stamp_ns=after + 5, frame_id="another_frame")))
    return out


# ---------------------------------------------------------------- one stream

class Peer:
    def __init__(self, domain):
        self.dp = DomainParticipant(domain)
        rel = Qos(Policy.Reliability.Reliable(duration(seconds=1)),
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


def run_stream(name, clouds, args, work, bad_after=None, config_sets=(), config=None):
    print(f"== {name}: {len(clouds)} clouds of {clouds[0]['height']}x{clouds[0]['width']}", flush=True)
    out = work / name
    out.mkdir(parents=True, exist_ok=True)
    bag = out / "reference.mcap"
    write_reference_bag(bag, clouds)
    ref_dir = out / "keylo-run"
    sets = []
    for s in ("output.exact=true",) + tuple(config_sets):
        sets += ["--set", s]
    cfg = [str(config)] if config else []
    r = subprocess.run([args.keylo, "-q", "run"] + cfg + ["--data", str(bag), "--out", str(ref_dir),
                        "--prefetch", "0"] + sets, capture_output=True, text=True)
    if not check(r.returncode == 0, f"{name}: keylo run on the reference bag: {r.stderr[-2000:]}"):
        return
    ref = read_tum(ref_dir / "trajectory.tum")

    node_dir = out / "keylo-ros2"
    log_path = out / "node.log"
    with open(log_path, "w") as log:
        node = subprocess.Popen(
            [args.keylo, "ros2"] + cfg + ["--out", str(node_dir), "--set", "ros2.input_reliability=reliable",
             "--set", f"ros2.domain_id={args.domain}"] + sets, stdout=log, stderr=log)
    peer = Peer(args.domain)
    try:
        if not check(peer.wait_matched(), f"{name}: the node's topics were not discovered"):
            return
        answers = []
        bad_sent = []
        for k, c in enumerate(clouds):
            peer.points.write(to_dds(c))
            msg, _ = peer.answer(args.answer_timeout)
            check(msg is not None, f"{name}: scan {k} (stamp {c['stamp_ns']}) was not answered")
            answers.append(msg)
            if bad_after is not None and k == bad_after:
                for fault, bad in bad_clouds(c, clouds[0]["stamp_ns"] - 10**9):
                    peer.points.write(to_dds(bad))
                    bad_sent.append(fault)
                    late, _ = peer.answer(0.5)
                    check(late is None, f"{name}: the bad cloud ({fault}) was answered")
        time.sleep(0.3)
        tfs = [s for s in peer.tf.take(N=1000) if isinstance(s, m.TFMessage)]
        paths = [s for s in peer.path.take(N=1000) if isinstance(s, m.Path)]
    finally:
        node.send_signal(signal.SIGINT)
        try:
            code = node.wait(timeout=30)
        except subprocess.TimeoutExpired:
            node.kill()
            code = "killed after 30 s"
    log_text = log_path.read_text()
    check(code == 0, f"{name}: the node's exit status after SIGINT is {code}")

    # The answers against keylo run on the same scans.
    got = [a for a in answers if a is not None]
    check(len(got) == len(clouds) == len(ref),
          f"{name}: {len(got)} answers, {len(clouds)} scans, {len(ref)} poses of keylo run")
    worst_t = worst_r = worst_stamp = 0.0
    for k, (a, c) in enumerate(zip(answers, clouds)):
        if a is None or k >= len(ref):
            continue
        p = a.pose.pose
        t = np.array([p.position.x, p.position.y, p.position.z])
        q = np.array([p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w])
        worst_t = max(worst_t, float(np.linalg.norm(t - ref[k, 1:4])))
        worst_r = max(worst_r, quat_angle(q, ref[k, 4:8]))
        stamp = a.header.stamp.sec * 10**9 + a.header.stamp.nanosec
        want, tol = end_stamp_ns(c)
        worst_stamp = max(worst_stamp, abs(stamp - want))
        check(abs(stamp - want) <= tol, f"{name}: scan {k}: stamp {stamp} ns, the scan's end {want} ns")
        check(abs(stamp * 1e-9 - ref[k, 0]) < 2e-6, f"{name}: scan {k}: stamp vs keylo run's {ref[k, 0]}")
        check(a.header.frame_id == "odom_lidar" and a.child_frame_id == c["frame_id"],
              f"{name}: scan {k}: frames {a.header.frame_id} -> {a.child_frame_id}")
        cov = np.array(a.pose.covariance).reshape(6, 6)
        check(np.allclose(cov, cov.T, rtol=1e-9, atol=1e-15), f"{name}: scan {k}: covariance not symmetric")
        check(np.linalg.eigvalsh(cov).min() > 0, f"{name}: scan {k}: covariance not positive definite")
    check(worst_t <= 1e-6 and worst_r <= 1e-6,
          f"{name}: poses differ from keylo run by up to {worst_t:.3e} m, {worst_r:.3e} rad")
    print(f"{name}: {len(got)}/{len(clouds)} answered; largest difference to keylo run "
          f"{worst_t:.2e} m, {worst_r:.2e} rad; stamps within {worst_stamp:.0f} ns of the scans' ends",
          flush=True)
    # TF and path follow the odometry.
    check(len(tfs) == len(got), f"{name}: {len(tfs)} /tf messages for {len(got)} answers")
    if tfs and got:
        tr = tfs[-1].transforms[0]
        last = got[-1].pose.pose.position
        check(tr.header.frame_id == "odom_lidar" and tr.child_frame_id == clouds[0]["frame_id"]
              and abs(tr.transform.translation.x - last.x) < 1e-12,
              f"{name}: the last /tf does not carry the last odometry")
    check(bool(paths) and len(paths[-1].poses) == len(got),
          f"{name}: the last path has {len(paths[-1].poses) if paths else 0} poses for {len(got)} answers")
    # Bad clouds: each logged with the topic and what is wrong.
    for fault in bad_sent:
        check(any(fault in line and "/points" in line for line in log_text.splitlines()),
              f"{name}: no log line naming /points and `{fault}`")
    # The node's files.
    summary = json.loads((node_dir / "summary.json").read_text())
    node_tum = read_tum(node_dir / "trajectory.tum")
    check(len(node_tum) == len(got) and summary["frames"] == len(got),
          f"{name}: the node's files hold {len(node_tum)} poses, summary {summary['frames']}")
    check(summary["ros2"]["clouds_refused"] == len(bad_sent),
          f"{name}: summary counts {summary['ros2']['clouds_refused']} refused clouds, {len(bad_sent)} sent")
    print(f"{name}: {len(bad_sent)} bad clouds refused and logged; the node went on", flush=True)


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


def run_control(clouds, gt, args, work):
    """Reset, set-pose and a motion prior, sent as a robot's other nodes would: a wheel
    odometry (here the simulator's ground truth) on a prior topic, a pose on keylo/set_pose,
    an Empty on keylo/reset."""
    name = "control"
    print(f"== {name}: {len(clouds)} clouds, motion prior, set_pose, reset", flush=True)
    out = work / name
    out.mkdir(parents=True, exist_ok=True)
    bag = out / "reference.mcap"
    write_reference_bag(bag, clouds)
    r = subprocess.run([args.keylo, "-q", "run", "--data", str(bag), "--out", str(out / "keylo-run"),
                        "--prefetch", "0", "--set", "output.exact=true"], capture_output=True, text=True)
    if not check(r.returncode == 0, f"{name}: keylo run: {r.stderr[-1500:]}"):
        return
    ref = read_tum(out / "keylo-run/trajectory.tum")
    with open(out / "node.log", "w") as log:
        node = subprocess.Popen(
            [args.keylo, "-v", "ros2", "--out", str(out / "keylo-ros2"),
             "--set", "ros2.input_reliability=reliable", "--set", f"ros2.domain_id={args.domain}",
             "--set", "ros2.motion_prior_topic=/wheel/odometry"], stdout=log, stderr=log)
    peer = Peer(args.domain)
    rel = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(100))
    wheel = DataWriter(peer.dp, Topic(peer.dp, "rt/wheel/odometry", m.Odometry), qos=rel)
    set_pose = DataWriter(peer.dp, Topic(peer.dp, "rt/keylo/set_pose", m.PoseWithCovarianceStamped), qos=rel)
    reset = DataWriter(peer.dp, Topic(peer.dp, "rt/keylo/reset", m.Empty), qos=rel)
    answers = []
    try:
        ok = peer.wait_matched()
        t0 = time.time()
        while ok and time.time() - t0 < 30 and min(
                w.get_publication_matched_status().current_count for w in (wheel, set_pose, reset)) == 0:
            time.sleep(0.05)
        def scan(k):
            c = clouds[k]
            g = gt[k]
            stamp = m.Time(sec=c["stamp_ns"] // 10**9, nanosec=c["stamp_ns"] % 10**9)
            o = m.Odometry(header=m.Header(stamp=stamp, frame_id="odom"), child_frame_id="base_link")
            o.pose.pose = m.Pose(position=m.Point(*g[1:4]), orientation=m.Quaternion(*g[4:8]))
            wheel.write(o)
            time.sleep(0.2)  # the prior arrives before the scan, as it would at 100 Hz
            peer.points.write(to_dds(c))
            msg, _ = peer.answer(args.answer_timeout)
            check(msg is not None, f"{name}: scan {k} not answered")
            answers.append(msg)
        for k in range(5):
            scan(k)
        # set_pose: the base is at (10, 5, 0), turned 90 degrees about z, from now on.
        target = m.Pose(position=m.Point(10.0, 5.0, 0.0),
                        orientation=m.Quaternion(0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5)))
        set_pose.write(m.PoseWithCovarianceStamped(header=m.Header(frame_id="odom_lidar"),
                                                   pose=m.PoseWithCovariance(pose=target)))
        time.sleep(0.3)
        scan(5)
        reset.write(m.Empty())
        time.sleep(0.3)
        scan(6)
        scan(7)
    finally:
        node.send_signal(signal.SIGINT)
        code = node.wait(timeout=30)
    check(code == 0, f"{name}: exit status {code}")
    if len(answers) < 8 or any(a is None for a in answers):
        return
    pos = lambda a: np.array([a.pose.pose.position.x, a.pose.pose.position.y, a.pose.pose.position.z])
    # With the prior (ground truth), the poses stay those of keylo run within centimetres.
    worst = max(float(np.linalg.norm(pos(answers[k]) - ref[k, 1:4])) for k in range(5))
    check(worst < 0.05, f"{name}: with the motion prior, poses {worst:.3f} m from keylo run's")
    # set_pose: scan 5 continues from the pose set, by the motion keylo run found.
    rel5 = np.linalg.inv(pose_matrix(ref[4, 1:4], ref[4, 4:8])) @ pose_matrix(ref[5, 1:4], ref[5, 4:8])
    want5 = msg_matrix(target) @ rel5
    err5 = float(np.linalg.norm(pos(answers[5]) - want5[:3, 3]))
    check(err5 < 0.05, f"{name}: after set_pose, scan 5 at {pos(answers[5])}, expected {want5[:3, 3]}")
    # reset: the next scan starts over at the identity.
    check(float(np.linalg.norm(pos(answers[6]))) == 0.0 and answers[6].pose.pose.orientation.w == 1.0,
          f"{name}: after reset, scan 6 at {pos(answers[6])}")
    summary = json.loads((out / "keylo-ros2/summary.json").read_text())["ros2"]
    # Every scan with a scan before it (not the first, not the first after the reset).
    check(summary["motion_priors_used"] == 6 and summary["poses_set"] == 1 and summary["resets"] == 1,
          f"{name}: node counts {summary}")
    print(f"{name}: motion prior used on {summary['motion_priors_used']} scans (poses within {worst:.3f} m "
          f"of keylo run); set_pose continued within {err5:.4f} m; reset started over at the identity",
          flush=True)


def run_debug(clouds, args, work, config):
    """Every debug topic on, a base frame with a mounting offset and /tf inverted: the extra
    messages arrive with their frames, and the base's odometry is A · T · A⁻¹ of keylo run's."""
    name = "debug-topics"
    print(f"== {name}: {len(clouds)} clouds, every debug topic, base_to_lidar, invert_odom_tf", flush=True)
    out = work / name
    out.mkdir(parents=True, exist_ok=True)
    bag = out / "reference.mcap"
    write_reference_bag(bag, clouds)
    r = subprocess.run([args.keylo, "-q", "run", str(config), "--data", str(bag), "--out",
                        str(out / "keylo-run"), "--prefetch", "0", "--set", "output.exact=true"],
                       capture_output=True, text=True)
    if not check(r.returncode == 0, f"{name}: keylo run: {r.stderr[-1500:]}"):
        return
    ref = read_tum(out / "keylo-run/trajectory.tum")
    mount = [0.1, -0.05, 0.5, 0.0, 0.0, math.sin(0.15), math.cos(0.15)]
    sets = ["ros2.input_reliability=reliable", f"ros2.domain_id={args.domain}",
            "ros2.base_frame=base_link", f"ros2.base_to_lidar=[{', '.join(map(str, mount))}]",
            "ros2.invert_odom_tf=true", "ros2.registered_cloud_topic=keylo/frame",
            "ros2.keypoint_cloud_topic=keylo/keypoints", "ros2.local_map_topic=keylo/local_map",
            "ros2.keypoint_image_topic=keylo/keypoint_image"]
    with open(out / "node.log", "w") as log:
        node = subprocess.Popen([args.keylo, "ros2", str(config)] + sum((["--set", x] for x in sets), []),
                                stdout=log, stderr=log)
    peer = Peer(args.domain)
    rel = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(100))
    extra = {t: DataReader(peer.dp, Topic(peer.dp, f"rt/keylo/{t}", ty), qos=rel)
             for t, ty in [("frame", m.PointCloud2), ("keypoints", m.PointCloud2),
                           ("local_map", m.PointCloud2), ("keypoint_image", m.Image)]}
    answers = []
    try:
        ok = peer.wait_matched()
        t0 = time.time()
        while ok and time.time() - t0 < 30 and min(
                rd.get_subscription_matched_status().current_count for rd in extra.values()) == 0:
            time.sleep(0.05)
        for c in clouds:
            peer.points.write(to_dds(c))
            msg, _ = peer.answer(args.answer_timeout)
            answers.append(msg)
        time.sleep(0.5)
        got = {t: [x for x in rd.take(N=100) if not type(x).__name__ == "InvalidSample"]
               for t, rd in extra.items()}
        tfs = [x for x in peer.tf.take(N=100) if isinstance(x, m.TFMessage)]
    finally:
        node.send_signal(signal.SIGINT)
        code = node.wait(timeout=30)
    check(code == 0, f"{name}: exit status {code}")
    if not check(all(a is not None for a in answers) and len(answers) == len(ref),
                 f"{name}: {sum(a is not None for a in answers)} answers of {len(ref)}"):
        return
    a_ = pose_matrix(mount[:3], mount[3:])
    worst = 0.0
    for k, a in enumerate(answers):
        want = a_ @ pose_matrix(ref[k, 1:4], ref[k, 4:8]) @ np.linalg.inv(a_)
        worst = max(worst, float(np.abs(msg_matrix(a.pose.pose) - want).max()))
        check(a.child_frame_id == "base_link", f"{name}: child frame {a.child_frame_id}")
    check(worst < 1e-6, f"{name}: base poses differ from A·T·A⁻¹ of keylo run by {worst:.2e}")
    n = len(answers)
    for t in ("frame", "keypoints", "local_map", "keypoint_image"):
        check(len(got[t]) == n, f"{name}: {len(got[t])} messages on keylo/{t} for {n} answers")
    frame_id = clouds[0]["frame_id"]
    check(all(c.header.frame_id == frame_id and c.width > 0 for c in got["frame"] + got["keypoints"]),
          f"{name}: registered/keypoint clouds not in {frame_id} or empty")
    check(all(c.header.frame_id == "odom_lidar" and c.width > 0 for c in got["local_map"]),
          f"{name}: local map not in odom_lidar or empty")
    if got["keypoint_image"]:
        img = got["keypoint_image"][-1]
        px = np.frombuffer(bytes(img.data), dtype=np.uint8).reshape(img.height, img.width, 3)
        red = int(((px[:, :, 0] == 255) & (px[:, :, 1] == 0)).sum())
        check(img.encoding == "rgb8" and red > 0, f"{name}: keypoint image {img.encoding}, {red} red pixels")
    if check(len(tfs) == n, f"{name}: {len(tfs)} /tf for {n} answers"):
        tr = tfs[-1].transforms[0]
        inv = np.linalg.inv(msg_matrix(answers[-1].pose.pose))
        check(tr.header.frame_id == "base_link" and tr.child_frame_id == "odom_lidar"
              and abs(tr.transform.translation.x - inv[0, 3]) < 1e-9,
              f"{name}: inverted /tf {tr.header.frame_id} -> {tr.child_frame_id}")
    print(f"{name}: {n} answers; base poses = A·T·A⁻¹ of keylo run within {worst:.1e}; "
          f"registered, keypoint and map clouds, keypoint pictures and inverted /tf for each", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keylo", required=True)
    ap.add_argument("--work", required=True, type=Path)
    ap.add_argument("--kitti", type=Path, help="a KITTI sequence folder (velodyne .bin files)")
    ap.add_argument("--kitti-frames", type=int, default=10)
    ap.add_argument("--sim-frames", type=int, default=15)
    ap.add_argument("--domain", type=int, default=17)
    ap.add_argument("--answer-timeout", type=float, default=60.0)
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    fixture = ROOT / "tests/fixtures/ros/ouster_ros2/ouster_ros2_0.mcap"
    # Real OS0-128 scans, organised (ouster-ros layout: t in ns, signal, reflectivity, ...).
    run_stream("ouster-organised", bag_clouds(fixture, "/ouster/points"), args, args.work, bad_after=1)
    # The paper's method on them: AKAZE keypoints in the cloud's own signal and range images.
    run_stream("ouster-akaze", bag_clouds(fixture, "/ouster/points"), args, args.work,
               config=ROOT / "configs/paper/outdoor-akaze-kiss-icp.toml")
    run_debug(bag_clouds(fixture, "/ouster/points"), args, args.work,
              ROOT / "configs/paper/outdoor-akaze-kiss-icp.toml")
    # The same scans unorganised, Velodyne-style (ring, time in s).
    run_stream("ouster-unorganised", bag_clouds(fixture, "/cloud_unorganised"), args, args.work)
    # Simulated road, KITTI-like clouds without point times.
    sim = args.work / "sim-road"
    r = subprocess.run([args.keylo, "-q", "sim", "--scene", "road", "--frames", str(args.sim_frames),
                        "--format", "kitti-bin", "--out", str(sim)], capture_output=True, text=True)
    if check(r.returncode == 0, f"keylo sim: {r.stderr[-1000:]}"):
        sim_clouds = kitti_bins(sim, args.sim_frames, 1_700_000_000_000_000_000)
        run_stream("sim-road", sim_clouds, args, args.work, bad_after=3)
        if len(sim_clouds) >= 8:
            run_control(sim_clouds, read_tum(sim / "gt.tum"), args, args.work)
    if args.kitti:
        run_stream("kitti", kitti_bins(args.kitti, args.kitti_frames, 1_317_000_000_000_000_000),
                   args, args.work, bad_after=4)
    if FAILURES:
        print(f"{len(FAILURES)} check(s) failed", flush=True)
        sys.exit(1)
    print("all checks passed", flush=True)


if __name__ == "__main__":
    main()
