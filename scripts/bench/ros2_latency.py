"""Latency of `keylo ros2`: from a cloud written by a Cyclone DDS peer to its odometry received
by the same peer, split into the peer's own `write()` (Cyclone's Python serialiser), the time
the node held the cloud (its ros2_frames.csv: taken from DDS → odometry published), of which
registration (keylo's stages), and the rest (DDS transport both ways, the peer's reading). Then a stream at
10 Hz: clouds answered and dropped, and the node's CPU % beside `keylo run --realtime` on the
same frames. Run inside a private network namespace (scripts/bench/ros2_latency.sh does).

  python ros2_latency.py --keylo target/release/keylo --work DIR --name NAME --bins FOLDER
         [--count N] [--stream-count N] [--hz 10]
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
sys.path.insert(0, str(HERE.parent / "ros2"))

from peer_common import Peer, kitti_bins, to_dds  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402
import ros2_idl as m  # noqa: E402


def start_node(args, out, reliability):
    log = open(out / "node.log", "w")
    return subprocess.Popen(
        [args.keylo, "-vv", "ros2", "--out", str(out / "keylo-ros2"),
         "--set", f"ros2.input_reliability={reliability}", "--set", f"ros2.domain_id={args.domain}",
         "--set", "ros2.path_topic=\"\""], stdout=log, stderr=log)


def stop(node):
    node.send_signal(signal.SIGINT)
    return node.wait(timeout=60)


def frames_csv(path):
    rows = Path(path).read_text().splitlines()
    head = rows[0].split(",")
    return [dict(zip(head, r.split(","))) for r in rows[1:]]


def latency(args, clouds, out):
    """One cloud at a time: write, wait for its answer."""
    out.mkdir(parents=True, exist_ok=True)
    node = start_node(args, out, "reliable")
    peer = Peer(args.domain)
    reset = DataWriter(peer.dp, Topic(peer.dp, "rt/keylo/reset", m.Empty), qos=peer.rel)
    peer.wait_matched()
    lat, writes = [], []
    try:
        for k in range(args.count):
            if k and k % len(clouds) == 0:
                # Another pass over the same scans: the node starts over, as after a jump.
                reset.write(m.Empty())
                time.sleep(0.2)
            c = dict(clouds[k % len(clouds)], stamp_ns=clouds[0]["stamp_ns"] + k * 100_000_000)
            msg = to_dds(c)
            t0 = time.perf_counter()
            peer.points.write(msg)
            writes.append(time.perf_counter() - t0)
            got, t1 = peer.answer(60.0)
            if got is None:
                sys.exit(f"cloud {k} not answered")
            lat.append(time.perf_counter() - t0)
            time.sleep(0.05)
    finally:
        stop(node)
    rows = frames_csv(out / "keylo-ros2/ros2_frames.csv")
    col = lambda name: np.array([float(r[name]) for r in rows])[: len(lat)]
    reg, node = col("odometry_ms"), col("in_node_ms")
    lat, writes = np.array(lat) * 1e3, np.array(writes) * 1e3
    # The first two frames of each pass set up the map; the steady state is what a robot sees.
    keep = np.array([k % len(clouds) >= min(2, len(clouds) - 1) for k in range(len(lat))])
    med = lambda a: round(float(np.median(a[keep])), 2)
    p99 = lambda a: round(float(np.percentile(a[keep], 99)), 2)
    both = lambda name, a: {f"{name}_ms_median": med(a), f"{name}_ms_p99": p99(a)}
    return dict(points=clouds[0]["width"] * clouds[0]["height"], frames=int(keep.sum()),
                **both("latency", lat), peer_write_ms_median=med(writes),
                **both("registration", reg), **both("node", node),
                **both("node_overhead", node - reg), **both("node_waited", col("waited_ms")),
                **both("node_prepare", col("prepare_ms")), **both("node_publish", col("publish_ms")),
                **both("transport", lat - writes - node), **both("keylo_share", lat - writes - reg))


def stream(args, clouds, out, bins):
    """Clouds at `hz` (best effort, as a driver publishes), counted on both sides."""
    out.mkdir(parents=True, exist_ok=True)
    node = start_node(args, out, "best-effort")
    peer = Peer(args.domain)
    peer.wait_matched()
    answers = 0
    t_start = time.perf_counter()
    try:
        for k in range(args.stream_count):
            due = t_start + k / args.hz
            while time.perf_counter() < due:
                answers += len(peer.odom.take(N=100))
                time.sleep(0.001)
            c = dict(clouds[k % len(clouds)], stamp_ns=clouds[0]["stamp_ns"] + k * int(1e9 / args.hz))
            peer.points.write(to_dds(c))
        t_end = time.perf_counter() + 5.0
        while time.perf_counter() < t_end and answers < args.stream_count:
            answers += len(peer.odom.take(N=100))
            time.sleep(0.01)
    finally:
        stop(node)
    summary = json.loads((out / "keylo-ros2/summary.json").read_text())
    rt = subprocess.run([args.keylo, "-q", "run", "--data", str(bins), "--realtime",
                         "--set", f"source.max_frames={args.stream_count}",
                         "--out", str(out / "keylo-run-realtime")], capture_output=True, text=True)
    rt_summary = json.loads((out / "keylo-run-realtime/summary.json").read_text()) if rt.returncode == 0 else {}
    return dict(sent=args.stream_count, answered=answers, **summary["ros2"],
                node_cpu_percent=summary.get("cpu_percent"), node_peak_rss_mb=summary.get("peak_rss_mb"),
                run_realtime_cpu_percent=rt_summary.get("cpu_percent"),
                run_realtime_peak_rss_mb=rt_summary.get("peak_rss_mb"))


def flood(args, clouds, out, count):
    """`count` clouds as fast as the peer writes them (best effort): registration falls behind,
    the node drops the oldest waiting clouds; its peak RSS must not grow with `count`."""
    out.mkdir(parents=True, exist_ok=True)
    node = start_node(args, out, "best-effort")
    peer = Peer(args.domain)
    peer.wait_matched()
    # Clouds cut to their first `flood_points` points, so the peer can write thousands quickly.
    n = args.flood_points
    msgs = [to_dds(dict(c, width=min(n, c["width"]), row_step=16 * min(n, c["width"]),
                        data=c["data"][:16 * n])) for c in clouds[:50]]
    try:
        for k in range(count):
            m_ = msgs[k % len(msgs)]
            stamp = clouds[0]["stamp_ns"] + k * 100_000_000
            m_.header.stamp.sec, m_.header.stamp.nanosec = stamp // 10**9, stamp % 10**9
            peer.points.write(m_)
            if k % 100 == 0:
                peer.odom.take(N=1000)
        time.sleep(2.0)
    finally:
        stop(node)
    summary = json.loads((out / "keylo-ros2/summary.json").read_text())
    return dict(sent=count, **summary["ros2"], peak_rss_mb=summary.get("peak_rss_mb"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keylo", required=True)
    ap.add_argument("--work", required=True, type=Path)
    ap.add_argument("--name", required=True)
    ap.add_argument("--bins", required=True, type=Path, help="folder of KITTI-style .bin scans")
    ap.add_argument("--count", type=int, default=30)
    ap.add_argument("--stream-count", type=int, default=0)
    ap.add_argument("--hz", type=float, default=10.0)
    ap.add_argument("--domain", type=int, default=19)
    ap.add_argument("--flood", type=int, nargs="*", default=[],
                    help="also flood the node with each of these many clouds (memory bound)")
    ap.add_argument("--flood-points", type=int, default=20_000)
    args = ap.parse_args()
    clouds = kitti_bins(args.bins, 10_000, 1_700_000_000_000_000_000)
    result = dict(name=args.name)
    if args.count:
        result["latency"] = latency(args, clouds, args.work / f"{args.name}-latency")
    if args.stream_count:
        result["stream"] = stream(args, clouds, args.work / f"{args.name}-stream", args.bins)
    for count in args.flood:
        result[f"flood_{count}"] = flood(args, clouds, args.work / f"{args.name}-flood-{count}", count)
    print(json.dumps(result, indent=1), flush=True)


if __name__ == "__main__":
    main()
