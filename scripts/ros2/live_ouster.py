"""`keylo ros2` reading an Ouster sensor's UDP packets itself (`[source] kind = "ouster-udp"`),
checked against an independent sender and consumer, inside a private network namespace
(scripts/ros2/netns.sh):

  - a few lines of Python read a real capture (pcap: Ethernet, IPv4 with fragments joined,
    UDP) and send its lidar datagrams to the node's port at the recorded pace, once whole and
    once with 5 % of them left out;
  - a Cyclone DDS peer receives `rt/keylo/odometry`;
  - the poses must equal `keylo run --data` on the capture (on a copy missing the same
    datagrams for the second pass), and the node's summary must count the lost packets.

  python live_ouster.py --keylo target/debug/keylo --work DIR [--pcap X.pcap --meta X.json]
"""

import argparse
import json
import random
import signal
import socket
import struct
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))

# peer_common sets CYCLONEDDS_URI before Cyclone DDS loads.
from peer_common import Peer, check, finish, quat_angle, read_tum  # noqa: E402

import numpy as np  # noqa: E402


def pcap_records(path):
    """(time s, raw Ethernet frame) of a classic pcap file."""
    data = Path(path).read_bytes()
    magic = struct.unpack("<I", data[:4])[0]
    endian = "<" if magic in (0xA1B2C3D4, 0xA1B23C4D) else ">"
    nano = magic in (0xA1B23C4D, 0x4D3CB2A1)
    pos = 24
    while pos + 16 <= len(data):
        sec, frac, incl, _orig = struct.unpack(endian + "IIII", data[pos:pos + 16])
        pos += 16
        yield sec + frac * (1e-9 if nano else 1e-6), data[pos:pos + incl]
        pos += incl


def udp_datagrams(path):
    """(time, destination port, payload) of every UDP datagram, IP fragments joined."""
    pending = {}
    for t, frame in pcap_records(path):
        if len(frame) < 34 or frame[12:14] != b"\x08\x00":
            continue
        ip = frame[14:]
        ihl = (ip[0] & 0x0F) * 4
        total = struct.unpack(">H", ip[2:4])[0]
        ident, flags = struct.unpack(">HH", ip[4:8])
        if ip[9] != 17:
            continue
        more, offset = flags & 0x2000, (flags & 0x1FFF) * 8
        body = ip[ihl:total]
        key = (ip[12:20], ident)
        if more or offset:
            parts = pending.setdefault(key, {})
            parts[offset] = body
            if not more:
                parts["end"] = offset + len(body)
            if "end" in parts:
                joined, at = b"", 0
                while at in parts:
                    joined += parts[at]
                    at += len(parts[at])
                if at == parts["end"]:
                    del pending[key]
                    body = joined
                else:
                    continue
            else:
                continue
        port = struct.unpack(">H", body[2:4])[0]
        yield t, port, body[8:]


def write_thinned(src, dst, lidar_port, drop):
    """A copy of the capture without the lidar datagrams `drop(i)` picks (whole datagrams,
    rewritten unfragmented)."""
    out = bytearray(Path(src).read_bytes()[:24])
    # Written as microsecond pcap, little endian, Ethernet.
    out[:24] = struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535 + 64, 1)
    i = 0
    for t, port, payload in udp_datagrams(src):
        if port == lidar_port:
            i += 1
            if drop(i - 1):
                continue
        udp = struct.pack(">HHHH", 7503, port, 8 + len(payload), 0) + payload
        ip = struct.pack(">BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), 0, 0, 64, 17, 0,
                         bytes([10, 0, 0, 2]), bytes([10, 0, 0, 1])) + udp
        frame = b"\xff" * 6 + b"\x02" * 6 + b"\x08\x00" + ip
        sec = int(t)
        out += struct.pack("<IIII", sec, int(round((t - sec) * 1e6)), len(frame), len(frame)) + frame
    Path(dst).write_bytes(bytes(out))


def send(src, lidar_port, to_port, drop, speed=1.0):
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    start, first, i, dropped = time.time(), None, 0, 0
    for t, port, payload in udp_datagrams(src):
        first = t if first is None else first
        wait = (t - first) / speed - (time.time() - start)
        if wait > 0:
            time.sleep(wait)
        if port != lidar_port:
            continue
        if drop(i):
            dropped += 1
        else:
            s.sendto(payload, ("127.0.0.1", to_port))
        i += 1
    return dropped


def run_pass(name, args, work, drop):
    out = work / name
    out.mkdir(parents=True, exist_ok=True)
    pcap = args.pcap
    if drop is not None:
        pcap = out / "thinned.pcap"
        write_thinned(args.pcap, pcap, 7502, drop)
    ref_dir = out / "keylo-run"
    r = subprocess.run([args.keylo, "-q", "run", "--data", str(pcap), "--meta", str(args.meta),
                        "--out", str(ref_dir), "--prefetch", "0", "--set", "output.exact=true"],
                       capture_output=True, text=True)
    if not check(r.returncode == 0, f"{name}: keylo run on the capture: {r.stderr[-1500:]}"):
        return
    ref = read_tum(ref_dir / "trajectory.tum")
    config = out / "live.toml"
    config.write_text(
        "[source]\nkind = \"ouster-udp\"\n"
        f"meta = \"{Path(args.meta).resolve()}\"\nbind = \"127.0.0.1\"\nlidar_port = {args.port}\n"
        "imu_port = 0\nidle_timeout_s = 2.0\n\n[output]\nexact = true\n\n"
        f"[ros2]\ndomain_id = {args.domain}\n")
    node_dir = out / "keylo-ros2"
    with open(out / "node.log", "w") as log:
        node = subprocess.Popen([args.keylo, "ros2", str(config), "--out", str(node_dir)],
                                stdout=log, stderr=log)
    peer = Peer(args.domain)
    try:
        t0 = time.time()
        while peer.odom.get_subscription_matched_status().current_count == 0 and time.time() - t0 < 30:
            time.sleep(0.05)
        dropped = send(args.pcap, 7502, args.port, drop or (lambda i: False))
        answers = []
        while True:
            msg, _ = peer.answer(5.0)
            if msg is None:
                break
            answers.append(msg)
        code = node.wait(timeout=30)
    finally:
        if node.poll() is None:
            node.send_signal(signal.SIGINT)
            node.wait(timeout=30)
    check(code == 0, f"{name}: the node's exit status {code} (log: {out / 'node.log'})")
    node_tum = read_tum(node_dir / "trajectory.tum")
    check(len(answers) == len(node_tum), f"{name}: {len(answers)} answers, {len(node_tum)} poses in the node's files")
    check(len(answers) >= len(ref) > 0, f"{name}: {len(answers)} answers, keylo run {len(ref)} poses")
    worst_t = worst_r = 0.0
    for k in range(min(len(ref), len(answers))):
        p = answers[k].pose.pose
        t = np.array([p.position.x, p.position.y, p.position.z])
        q = np.array([p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w])
        worst_t = max(worst_t, float(np.linalg.norm(t - ref[k, 1:4])))
        worst_r = max(worst_r, quat_angle(q, ref[k, 4:8]))
        stamp = answers[k].header.stamp.sec * 10**9 + answers[k].header.stamp.nanosec
        check(abs(stamp * 1e-9 - ref[k, 0]) < 1e-6, f"{name}: answer {k} stamped {stamp}, keylo run {ref[k, 0]}")
        check(answers[k].child_frame_id == "os_sensor", f"{name}: child frame {answers[k].child_frame_id}")
    check(worst_t <= 1e-6 and worst_r <= 1e-6,
          f"{name}: poses differ from keylo run by {worst_t:.3e} m, {worst_r:.3e} rad")
    summary = json.loads((node_dir / "summary.json").read_text())
    lost = summary.get("source_counters", {}).get("packets_lost", 0)
    if drop is None:
        check(lost == 0, f"{name}: {lost} packets counted lost with none dropped")
    else:
        check(lost > 0, f"{name}: {dropped} datagrams dropped, none counted lost")
    log = (out / "node.log").read_text()
    if drop is not None:
        check("packets lost" in log, f"{name}: no log line says packets were lost")
    print(f"{name}: {len(answers)} answers ({len(ref)} frames of keylo run on the capture); largest "
          f"difference {worst_t:.1e} m, {worst_r:.1e} rad; {dropped} datagrams dropped, "
          f"{lost} packets counted lost", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keylo", required=True)
    ap.add_argument("--work", required=True, type=Path)
    fixture = "tests/fixtures/ouster/OS-0-128_v3.0.1_1024x10_from_osf"
    ap.add_argument("--pcap", type=Path, default=ROOT / f"{fixture}.pcap")
    ap.add_argument("--meta", type=Path, default=ROOT / f"{fixture}.json")
    ap.add_argument("--port", type=int, default=17502)
    ap.add_argument("--domain", type=int, default=18)
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    run_pass("ouster-udp", args, args.work, None)
    rng = random.Random(5)
    picked = {i for i in range(100_000) if rng.random() < 0.05}
    run_pass("ouster-udp-5pct-lost", args, args.work, lambda i: i in picked)
    finish()


if __name__ == "__main__":
    main()
