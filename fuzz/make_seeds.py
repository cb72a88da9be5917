"""Writes the seed corpora of the fuzz targets (fuzz/corpus/<target>/), from the repository's
own fixtures (Ouster samples: BSD-3, tests/fixtures/ouster/; keylo's configs; evo fixtures made
by tests/fixtures/evo/make_fixtures.py) and tiny files made here. Never from KITTI data.

Run from the repository root (the mcap seed needs `pip install mcap==1.6.0`):
    python3 fuzz/make_seeds.py
then minimise with `cargo fuzz cmin` (scripts/fuzz.sh --cmin). Multi-file targets join their
files with SEP (crates/keylo-fuzz/src/parts.rs).
"""
import json
import os
import struct
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "fuzz", "corpus")
OUSTER = os.path.join(ROOT, "tests", "fixtures", "ouster")
SEP = b"\n--keylo-fuzz-part--\n"
# The order of METADATA in crates/keylo-fuzz/src/ouster.rs.
METADATA = [
    "OS-0-32-U1_v2.2.0_1024x10", "OS-1-32-G_v2.1.1_1024x10", "OS-1-64_1024x10_fw20",
    "OS-1-128_v2.3.0_1024x10_lb_n3", "OS-2-128-U1_v2.3.0_1024x10",
    "OS-0-128_v3.0.1_1024x10_from_osf", "OS-0-128_v3.2.0-rc7_2048x10_dual_from_osf", "crc_test",
]


def write(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def read(path):
    with open(path, "rb") as f:
        return f.read()


def truncated_pcap(data, limit):
    """The global header and the first packets of a pcap, at most `limit` bytes."""
    out, pos = bytearray(data[:24]), 24
    while pos + 16 <= len(data):
        incl = struct.unpack_from("<I", data, pos + 8)[0]
        if len(out) + 16 + incl > limit:
            break
        out += data[pos:pos + 16 + incl]
        pos += 16 + incl
    return bytes(out)


def ouster():
    for i, name in enumerate(METADATA):
        write("ouster_metadata", name + ".json", read(os.path.join(OUSTER, name + ".json")))
        pcap = os.path.join(OUSTER, name + ".pcap")
        if os.path.exists(pcap):
            write("ouster_pcap", name + ".pcap", bytes([i]) + truncated_pcap(read(pcap), 60_000))


# ROS messages, ROS1 serialisation and CDR (little-endian, aligned after the 4-byte header).
class Ros1:
    def __init__(self):
        self.b = bytearray()

    def u8(self, v):
        self.b += struct.pack("<B", v)

    def u32(self, v):
        self.b += struct.pack("<I", v)

    def string(self, s):
        self.u32(len(s)); self.b += s.encode()

    def blob(self, data):
        self.u32(len(data)); self.b += data

    def header(self, sec, nsec):
        self.u32(0); self.u32(sec); self.u32(nsec); self.string("os_sensor")


class Cdr(Ros1):
    def __init__(self):
        self.b = bytearray(b"\x00\x01\x00\x00")

    def align(self, n):
        while (len(self.b) - 4) % n:
            self.b.append(0)

    def u32(self, v):
        self.align(4); super().u32(v)

    def string(self, s):
        self.u32(len(s) + 1); self.b += s.encode() + b"\0"

    def header(self, sec, nsec):
        self.u32(sec); self.u32(nsec); self.string("os_sensor")


FIELDS = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("intensity", 12, 7), ("t", 16, 6),
          ("ring", 20, 4)]


def cloud(w, rows, cols, sec):
    """An organised cloud of rows x cols points, point_step 24."""
    w.header(sec, 0)
    w.u32(rows); w.u32(cols)
    w.u32(len(FIELDS))
    for name, off, dt in FIELDS:
        w.string(name); w.u32(off); w.u8(dt); w.u32(1)
    w.u8(0); w.u32(24); w.u32(24 * cols)
    data = bytearray()
    for r in range(rows):
        for c in range(cols):
            data += struct.pack("<4fIH2x", 1.0 + c, 0.5 * r, 0.1 * r, 10.0 * c, 1000 * c, r)
    w.blob(bytes(data)); w.u8(1)
    return bytes(w.b)


def image(w, rows, cols, sec):
    w.header(sec, 0)
    w.u32(rows); w.u32(cols); w.string("mono16"); w.u8(0); w.u32(2 * cols)
    w.blob(bytes(range(2 * rows * cols)))
    return bytes(w.b)


def messages():
    for sel, w in [(0, Ros1), (1, Cdr)]:
        write("ros_messages", f"cloud_{w.__name__.lower()}", bytes([sel]) + cloud(w(), 2, 4, 1))
        write("ros_messages", f"image_{w.__name__.lower()}", bytes([sel | 2]) + image(w(), 2, 4, 1))
    unorganised = cloud(Ros1(), 1, 8, 1)
    write("ros_messages", "cloud_unorganised_ros1", b"\0" + unorganised)


def record(fields, data):
    h = b"".join(struct.pack("<I", len(k) + 1 + len(v)) + k + b"=" + v for k, v in fields)
    return struct.pack("<I", len(h)) + h + struct.pack("<I", len(data)) + data


def ros1_bag():
    """An uncompressed, indexed ROS1 bag: cloud + signal image on two frames."""
    topics = [("/ouster/points", "sensor_msgs/PointCloud2"), ("/ouster/signal_image", "sensor_msgs/Image")]
    conns = []
    for cid, (topic, typ) in enumerate(topics):
        conn_header = record([(b"topic", topic.encode()), (b"type", typ.encode()),
                              (b"md5sum", b"*"), (b"message_definition", b"")], b"")
        conn_header = conn_header[4:-4]  # the connection header is the record's data
        conns.append(record([(b"op", b"\x07"), (b"conn", struct.pack("<I", cid)),
                             (b"topic", topic.encode())], conn_header))
    msgs, chunk = [], bytearray(b"".join(conns))
    for i, sec in enumerate([1, 2]):
        for cid, make in enumerate([cloud, image]):
            t = struct.pack("<II", sec, 20_000_000)
            msgs.append((cid, t, len(chunk)))
            chunk += record([(b"op", b"\x02"), (b"conn", struct.pack("<I", cid)), (b"time", t)],
                            make(Ros1(), 2, 4, sec))
    chunk_pos = 13 + 4096
    t0, t1 = struct.pack("<II", 1, 0), struct.pack("<II", 2, 20_000_000)
    chunk_rec = record([(b"op", b"\x05"), (b"compression", b"none"),
                        (b"size", struct.pack("<I", len(chunk)))], bytes(chunk))
    index = b""
    for cid in range(len(topics)):
        entries = [m for m in msgs if m[0] == cid]
        index += record([(b"op", b"\x04"), (b"ver", struct.pack("<I", 1)),
                         (b"conn", struct.pack("<I", cid)), (b"count", struct.pack("<I", len(entries)))],
                        b"".join(t + struct.pack("<I", off) for _, t, off in entries))
    index_pos = chunk_pos + len(chunk_rec) + len(index)
    info = record([(b"op", b"\x06"), (b"ver", struct.pack("<I", 1)), (b"chunk_pos", struct.pack("<Q", chunk_pos)),
                   (b"start_time", t0), (b"end_time", t1), (b"count", struct.pack("<I", len(topics)))],
                  b"".join(struct.pack("<II", cid, 2) for cid in range(len(topics))))
    header = record([(b"op", b"\x03"), (b"index_pos", struct.pack("<Q", index_pos)),
                     (b"conn_count", struct.pack("<I", len(topics))), (b"chunk_count", struct.pack("<I", 1))], b"")
    # The bag header record is padded with spaces to 4096 bytes (rosbag's layout).
    hdr = header[: len(header) - 4]
    data_len = 4096 - len(hdr) - 4
    header = hdr + struct.pack("<I", data_len) + b" " * data_len
    bag = b"#ROSBAG V2.0\n" + header
    assert len(bag) == chunk_pos, (len(bag), chunk_pos)
    bag += chunk_rec + index + b"".join(conns) + info
    write("ros1_bag", "two_frames.bag", bag)
    write("ros1_bag", "two_frames_unindexed.bag", bag[: chunk_pos + len(chunk_rec)])


def mcap():
    try:
        from mcap.writer import CompressionType, Writer
    except ImportError:
        print("mcap not installed: no mcap seed", file=sys.stderr)
        return
    import io
    for name, comp in [("two_frames.mcap", CompressionType.NONE), ("two_frames_lz4.mcap", CompressionType.LZ4)]:
        out = io.BytesIO()
        w = Writer(out, compression=comp)
        w.start("ros2", "keylo-fuzz")
        ids = {}
        for topic, typ in [("/ouster/points", "sensor_msgs/msg/PointCloud2"),
                           ("/ouster/signal_image", "sensor_msgs/msg/Image")]:
            sid = w.register_schema(name=typ, encoding="ros2msg", data=b"")
            ids[topic] = w.register_channel(topic=topic, message_encoding="cdr", schema_id=sid)
        for sec in [1, 2]:
            t = sec * 1_000_000_000 + 20_000_000
            w.add_message(ids["/ouster/points"], log_time=t, data=cloud(Cdr(), 2, 4, sec), publish_time=t)
            w.add_message(ids["/ouster/signal_image"], log_time=t, data=image(Cdr(), 2, 4, sec), publish_time=t)
        w.finish()
        write("mcap", name, out.getvalue())


def ros2_db3():
    """A ROS 2 sqlite3 bag (rosbag2's Humble schema, written with Python's sqlite3) holding
    the two clouds and images of the mcap seed."""
    import sqlite3
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "two_frames.db3")
        c = sqlite3.connect(path)
        c.executescript(
            "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
            "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
            " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
            "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
            " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
            "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
            "INSERT INTO schema VALUES (3, 'humble');")
        c.execute("INSERT INTO topics VALUES (1, '/ouster/points', 'sensor_msgs/msg/PointCloud2', 'cdr', '')")
        c.execute("INSERT INTO topics VALUES (2, '/ouster/signal_image', 'sensor_msgs/msg/Image', 'cdr', '')")
        for sec in [1, 2]:
            t = sec * 1_000_000_000 + 20_000_000
            c.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (1, ?, ?)",
                      (t, bytes(cloud(Cdr(), 2, 4, sec))))
            c.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (2, ?, ?)",
                      (t, bytes(image(Cdr(), 2, 4, sec))))
        c.commit()
        c.close()
        with open(path, "rb") as f:
            write("ros2_db3", "two_frames.db3", f.read())


def point_files():
    pts = [(1.0, 2.0, 3.0, 10.0), (-1.0, 0.5, 0.0, 20.0), (4.0, -2.0, 1.0, 30.0)]
    head = "ply\nformat {}\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\nend_header\n"
    write("ply", "ascii.ply", (head.format("ascii 1.0") + "".join("%g %g %g %g\n" % p for p in pts)).encode())
    for enc, e in [("binary_little_endian 1.0", "<"), ("binary_big_endian 1.0", ">")]:
        body = b"".join(struct.pack(e + "4f", *p) for p in pts)
        write("ply", enc.split()[0] + ".ply", head.format(enc).encode() + body)
    faces = head.format("ascii 1.0").replace("end_header", "element face 1\nproperty list uchar int vertex_indices\nend_header")
    write("ply", "with_faces.ply", (faces + "".join("%g %g %g %g\n" % p for p in pts) + "3 0 1 2\n").encode())
    pcd = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH {w}\nHEIGHT {h}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA {d}\n"
    write("pcd", "ascii.pcd", (pcd.format(w=3, h=1, d="ascii") + "".join("%g %g %g %g\n" % p for p in pts)).encode())
    body = b"".join(struct.pack("<4f", *p) for p in pts)
    write("pcd", "binary.pcd", pcd.format(w=3, h=1, d="binary").encode() + body)
    # binary_compressed: field-major data, LZF-compressed as literal runs only.
    raw = b"".join(struct.pack("<3f", *[p[k] for p in pts]) for k in range(4))
    lzf = b"".join(bytes([len(raw[i:i + 32]) - 1]) + raw[i:i + 32] for i in range(0, len(raw), 32))
    comp = struct.pack("<II", len(lzf), len(raw)) + lzf
    write("pcd", "binary_compressed.pcd", pcd.format(w=3, h=1, d="binary_compressed").encode() + comp)
    organised = pcd.replace("POINTS 3", "POINTS 4").format(w=2, h=2, d="ascii")
    write("pcd", "organised.pcd", (organised + "".join("%g %g %g %g\n" % p for p in pts + [pts[0]])).encode())


def kitti():
    scan = b"".join(struct.pack("<4f", *p) for p in [(5.0, 1.0, -1.0, 0.3), (-3.0, 2.0, 0.5, 0.9), (10.0, -4.0, 0.0, 0.1)])
    write("kitti_bin", "three_points.bin", scan)
    times = b"0.000000e+00\n"
    calib = b"P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr: 0 -1 0 0 0 0 -1 0 1 0 0 -0.1\n"
    poses = b"1 0 0 0 0 1 0 0 0 0 1 0\n"
    write("kitti_folder", "scan_times_calib_poses", SEP.join([scan, times, calib, poses]))
    write("kitti_folder", "scan_only", scan)


def klf(rows=2, cols=3):
    b = bytearray(b"KLF1") + struct.pack("<IIQd", rows, cols, 0, 1.5)
    b += struct.pack(f"<{cols}d", *[1.5 + 0.01 * c for c in range(cols)])
    n = rows * cols
    for k in range(4):
        b += struct.pack(f"<{n}f", *[float(i + k) for i in range(n)])
    b += struct.pack(f"<{3 * n}f", *[0.5 * i for i in range(3 * n)])
    b += bytes([i % 2 for i in range(n)])
    return bytes(b)


def frames():
    write("klf", "two_by_three.klf", klf())
    manifest = {"format": "keylo-frames", "version": 1, "rows": 2, "cols": 3, "frames": 1,
                "beams": {"model": "fuzz", "altitude_deg": [1.0, -1.0], "azimuth_deg": [0.0, 0.0],
                          "origin_to_beam_mm": 0.0, "columns_per_frame": 3, "frame_rate_hz": 10.0},
                "description": "seed"}
    write("frames_folder", "one_frame", SEP.join([json.dumps(manifest).encode(), klf()]))


def text():
    configs = os.path.join(ROOT, "configs")
    for dirpath, _, names in os.walk(configs):
        for n in sorted(names):
            if n.endswith(".toml"):
                rel = os.path.relpath(os.path.join(dirpath, n), configs).replace(os.sep, "_")
                write("config_toml", rel, read(os.path.join(dirpath, n)))
    evo = os.path.join(ROOT, "tests", "fixtures", "evo")
    head = lambda p, n: b"".join(read(p).splitlines(keepends=True)[:n])
    write("trajectory_tum", "smooth_gt.tum", head(os.path.join(evo, "smooth_gt.tum"), 12))
    write("trajectory_tum", "comments.tum", b"# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n\n0.1 1 0 0 0 0 0.0998 0.995\n")
    kitti_gt = head(os.path.join(evo, "kitti_gt.txt"), 12)
    write("trajectory_kitti", "kitti_gt.txt", kitti_gt)
    write("trajectory_kitti", "with_times", kitti_gt + SEP + b"\n".join(b"%d" % i for i in range(12)))


def plugin():
    def c(s):
        return bytes([len(s)]) + s
    base = bytes([1]) + c(b"fuzz") + c(b"1.0") + bytes([0])
    write("plugin_table", "detector", base + bytes([1, 1]) + c(b"detects") + bytes([0b0001111]))
    kinds = b"".join(bytes([s]) + c(b"k") + bytes([0b111 | (8 << (s - 1))]) for s in [1, 2, 3, 4])
    write("plugin_table", "four_stages", base + bytes([4]) + kinds)
    write("plugin_table", "bad_utf8_name", bytes([1]) + c(b"\xff\xfe") + c(b"") + bytes([0, 1, 1, 0xff, 0x0f]))


if __name__ == "__main__":
    ouster(); messages(); ros1_bag(); mcap(); ros2_db3(); point_files(); kitti(); frames(); text(); plugin()
