"""Control inputs and debug outputs of `keylo ros2` against a Cyclone DDS peer (called by
interop.py, inside its network namespace): a motion prior, set-pose and reset as a robot's other
nodes send them; every debug topic with a mounting extrinsic and inverted /tf."""

import json
import math
import signal
import subprocess
import time

import numpy as np

import ros2_idl as m
from cyclonedds.core import Policy, Qos
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration
from peer_common import Peer, check, msg_matrix, pose_matrix, reference_run, to_dds


def run_control(clouds, gt, args, work):
    """Reset, set-pose and a motion prior, sent as a robot's other nodes would: a wheel
    odometry (here the simulator's ground truth) on a prior topic, a pose on keylo/set_pose,
    an Empty on keylo/reset."""
    name = "control"
    print(f"== {name}: {len(clouds)} clouds, motion prior, set_pose, reset", flush=True)
    out = work / name
    out.mkdir(parents=True, exist_ok=True)
    ref = reference_run(name, args.keylo, clouds, out)
    if ref is None:
        return
    with open(out / "node.log", "w") as log:
        node = subprocess.Popen(
            [args.keylo, "-v", "ros2", "--out", str(out / "keylo-ros2"), "--map-out", str(out / "map"),
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
    # The reset finished the map of the scans before it and started another for those after.
    maps = [json.loads((out / d / "map.json").read_text()) for d in ("map", "map-1")]
    check([mp["frames"] for mp in maps] == [6, len(answers) - 6],
          f"{name}: maps before and after the reset hold {[mp['frames'] for mp in maps]} frames")
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
    ref = reference_run(name, args.keylo, clouds, out, config)
    if ref is None:
        return
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




def run_localise_control(clouds, args, work, config):
    """A localising node (`[registrar] kind = "localise"`) told a pose far off on
    keylo/set_pose: the next scan is not tracking, so nothing is published for it and the log
    says so; told the right pose, it tracks again on keylo run's poses."""
    name = "localise-control"
    print(f"== {name}: {len(clouds)} clouds, set_pose far off, then back", flush=True)
    out = work / name
    out.mkdir(parents=True, exist_ok=True)
    ref = reference_run(name, args.keylo, clouds, out, config)
    if ref is None:
        return
    with open(out / "node.log", "w") as log:
        node = subprocess.Popen(
            [args.keylo, "ros2", str(config), "--out", str(out / "keylo-ros2"),
             "--set", "ros2.input_reliability=reliable", "--set", f"ros2.domain_id={args.domain}"],
            stdout=log, stderr=log)
    peer = Peer(args.domain)
    rel = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(100))
    set_pose = DataWriter(peer.dp, Topic(peer.dp, "rt/keylo/set_pose", m.PoseWithCovarianceStamped), qos=rel)
    answers = {}
    try:
        ok = peer.wait_matched()
        t0 = time.time()
        while ok and time.time() - t0 < 30 and set_pose.get_publication_matched_status().current_count == 0:
            time.sleep(0.05)

        def scan(k, timeout):
            peer.points.write(to_dds(clouds[k]))
            answers[k], _ = peer.answer(timeout)

        def tell(pose):
            set_pose.write(m.PoseWithCovarianceStamped(header=m.Header(frame_id="odom_lidar"),
                                                       pose=m.PoseWithCovariance(pose=pose)))
            time.sleep(0.3)
        for k in range(4):
            scan(k, args.answer_timeout)
        tell(m.Pose(position=m.Point(ref[3, 1] + 10.0, ref[3, 2] + 5.0, ref[3, 3]),
                    orientation=m.Quaternion(0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5))))
        scan(4, 5.0)
        tell(m.Pose(position=m.Point(*ref[4, 1:4]), orientation=m.Quaternion(*ref[4, 4:8])))
        scan(5, args.answer_timeout)
    finally:
        node.send_signal(signal.SIGINT)
        code = node.wait(timeout=30)
    check(code == 0, f"{name}: exit status {code}")
    pos = lambda a: np.array([a.pose.pose.position.x, a.pose.pose.position.y, a.pose.pose.position.z])
    check(all(answers.get(k) is not None for k in range(4)), f"{name}: scans 0-3 not all answered")
    worst = max((float(np.linalg.norm(pos(answers[k]) - ref[k, 1:4])) for k in range(4)
                 if answers.get(k) is not None), default=float("inf"))
    check(worst < 1e-6, f"{name}: scans 0-3 {worst:.2e} m from keylo run's poses")
    check(answers.get(4) is None, f"{name}: scan 4, localised from 11 m off, was published")
    log_text = (out / "node.log").read_text()
    check("not tracking in the map" in log_text and "nothing published" in log_text,
          f"{name}: no log line saying scan 4 was not tracking")
    err5 = float(np.linalg.norm(pos(answers[5]) - ref[5, 1:4])) if answers.get(5) is not None else float("inf")
    check(err5 < 0.05, f"{name}: after set_pose back, scan 5 is {err5:.3f} m from keylo run's pose")
    summary = json.loads((out / "keylo-ros2/summary.json").read_text())["ros2"]
    check(summary["frames_not_tracking"] == 1 and summary["poses_set"] == 2,
          f"{name}: node counts {summary}")
    print(f"{name}: scans on keylo run's poses; the scan localised from 11 m off was not published "
          f"and was logged; set back, scan 5 within {err5:.4f} m", flush=True)
