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
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

# peer_common sets CYCLONEDDS_URI before Cyclone DDS loads.
from peer_common import (  # noqa: E402
    ROOT, Peer, bag_clouds, check, end_stamp_ns, finish, kitti_bins, quat_angle, read_map_ply,
    read_tum, records, reference_run, to_dds)
from interop_control import run_localise_control, run_control, run_debug  # noqa: E402
import ros2_idl as m  # noqa: E402

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


def run_stream(name, clouds, args, work, bad_after=None, config_sets=(), config=None):
    print(f"== {name}: {len(clouds)} clouds of {clouds[0]['height']}x{clouds[0]['width']}", flush=True)
    out = work / name
    out.mkdir(parents=True, exist_ok=True)
    ref = reference_run(name, args.keylo, clouds, out, config, config_sets)
    if ref is None:
        return
    sets = sum((["--set", s] for s in ("output.exact=true",) + tuple(config_sets)), [])
    cfg = [str(config)] if config else []

    node_dir = out / "keylo-ros2"
    log_path = out / "node.log"
    with open(log_path, "w") as log:
        node = subprocess.Popen(
            [args.keylo, "ros2"] + cfg + ["--out", str(node_dir), "--map-out", str(out / "keylo-ros2-map"),
             "--record", str(out / "node.mcap"),
             "--set", "ros2.input_reliability=reliable",
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
    # The node's map is the map keylo run saves from the same scans.
    node_map = json.loads((out / "keylo-ros2-map" / "map.json").read_text())
    run_map = json.loads((out / "keylo-run-map" / "map.json").read_text())
    a, b = read_map_ply(out / "keylo-ros2-map" / "map.ply"), read_map_ply(out / "keylo-run-map" / "map.ply")
    same = a.shape == b.shape and float(np.abs(a - b).max(initial=0.0)) <= 1e-4
    check(node_map["frames"] == len(got) and (node_map["points"], node_map["keyframes"])
          == (run_map["points"], run_map["keyframes"]) and same,
          f"{name}: the node's map ({node_map['points']} points, {node_map['keyframes']} keyframes) "
          f"is not keylo run's ({run_map['points']}, {run_map['keyframes']})")
    print(f"{name}: the node's map holds keylo run's {run_map['points']} points and "
          f"{run_map['keyframes']} keyframes", flush=True)
    check_recording(name, out / "node.mcap", got)


def check_recording(name, path, answers):
    """`keylo ros2 --record`: a pose per answer, the last one the last odometry published."""
    from mcap.reader import make_reader
    from mcap_protobuf.decoder import DecoderFactory

    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        poses = [d for _, _, _, d in reader.iter_decoded_messages(topics=["/keylo/pose"])]
        scans = sum(1 for _ in reader.iter_messages(topics=["/keylo/scan"]))
    check(len(poses) == len(answers) == scans,
          f"{name}: the recording holds {len(poses)} poses and {scans} scans for {len(answers)} answers")
    if poses and answers:
        a, b = poses[-1].pose.position, answers[-1].pose.pose.position
        check(max(abs(a.x - b.x), abs(a.y - b.y), abs(a.z - b.z)) < 1e-9,
              f"{name}: the recording's last pose is not the last odometry published")
    print(f"{name}: the node's recording holds {len(poses)} poses and scans, the last its odometry",
          flush=True)


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
        # Localisation (`[registrar] kind = "localise"`) in the map keylo run saved from the
        # same scans: the node's poses are keylo run's with the same config.
        loc = args.work / "sim-road-localise.toml"
        loc_map = (args.work / "sim-road" / "keylo-run-map").as_posix()
        loc.write_text(f'[registrar]\nkind = "localise"\nmap = "{loc_map}"\n')
        run_stream("sim-road-localise", sim_clouds, args, args.work, config=loc)
        run_localise_control(sim_clouds, args, args.work, loc)
        if len(sim_clouds) >= 8:
            run_control(sim_clouds, read_tum(sim / "gt.tum"), args, args.work)
    if args.kitti:
        run_stream("kitti", kitti_bins(args.kitti, args.kitti_frames, 1_317_000_000_000_000_000),
                   args, args.work, bad_after=4)
    finish()


if __name__ == "__main__":
    main()
