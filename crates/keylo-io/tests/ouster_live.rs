//! Source kind `ouster-udp`: a real capture's lidar packets sent over UDP give the frames of
//! the capture read as a pcap, bit for bit; with 5 % of the packets dropped, the frames of a
//! capture missing the same packets, and the loss is counted.
//!
//! Network rule: the test sends and receives UDP, so it runs in a private network namespace
//! (loopback only): when not in one, it runs itself again under `scripts/ros2/netns.sh`.

use std::fs::File;
use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use keylo_core::{BuildContext, ImageSource, LidarFrame};
use keylo_io::ouster::{OusterSource, OusterSourceConfig, OusterUdpConfig, UdpReader};
use pcap_file::pcap::{PcapPacket, PcapReader, PcapWriter};

const SAMPLE: &str = "OS-0-128_v3.0.1_1024x10_from_osf";
const PORT: u16 = 17502;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ouster")
}

fn meta() -> String {
    fixtures()
        .join(format!("{SAMPLE}.json"))
        .display()
        .to_string()
}

fn ctx() -> BuildContext {
    BuildContext {
        base_dir: PathBuf::from("."),
        ..Default::default()
    }
}

/// Runs `test` inside a private network namespace: directly when already in one, else this
/// test binary again under scripts/ros2/netns.sh.
fn in_netns(name: &str, test: impl FnOnce()) {
    if std::env::var("KEYLO_IN_NETNS").as_deref() == Ok("1") {
        return test();
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/ros2/netns.sh");
    let exe = std::env::current_exe().expect("the test binary");
    let status = std::process::Command::new("bash")
        .arg(&script)
        .arg(exe)
        .args(["--exact", name, "--nocapture", "--test-threads", "1"])
        .status()
        .expect("scripts/ros2/netns.sh runs");
    assert!(
        status.success(),
        "{name} in a private network namespace: {status}"
    );
}

fn pcap_frames(pcap: &Path) -> (Vec<LidarFrame>, Vec<(String, u64)>) {
    let config = OusterSourceConfig {
        path: pcap.display().to_string(),
        meta: meta(),
        ..OusterSourceConfig::default()
    };
    let mut s = OusterSource::open(&config, &ctx()).expect("opens");
    let frames = std::iter::from_fn(|| s.next_frame())
        .map(|f| f.expect("frame"))
        .collect();
    (frames, s.counters())
}

/// Sends the capture's UDP payloads to the port at their recorded pace (times `speed`),
/// leaving out the datagrams `drop(i)` picks; returns how many were left out.
fn send(pcap: &Path, speed: f64, drop: impl Fn(usize) -> bool) -> usize {
    let socket = UdpSocket::bind("127.0.0.1:0").expect("sender socket");
    let mut reader = UdpReader::open(pcap).expect("capture");
    let start = Instant::now();
    let mut first: Option<f64> = None;
    let mut dropped = 0;
    let mut i = 0;
    while let Some(d) = reader.next_datagram() {
        let d = d.expect("datagram");
        let t0 = *first.get_or_insert(d.time);
        let due = Duration::from_secs_f64((d.time - t0).max(0.0) / speed);
        if let Some(wait) = due.checked_sub(start.elapsed()) {
            std::thread::sleep(wait);
        }
        // Only the lidar port's datagrams go to the lidar port (IMU packets have their own).
        if d.dst_port == 7502 {
            if drop(i) {
                dropped += 1;
            } else {
                socket
                    .send_to(&d.payload, ("127.0.0.1", PORT))
                    .expect("sends");
            }
            i += 1;
        }
    }
    dropped
}

fn live_frames(
    sender: impl FnOnce() -> usize + Send,
) -> (Vec<LidarFrame>, Vec<(String, u64)>, usize) {
    let config = OusterUdpConfig {
        meta: meta(),
        bind: "127.0.0.1".into(),
        lidar_port: PORT,
        imu_port: 0,
        idle_timeout_s: 1.0,
        ..OusterUdpConfig::default()
    };
    let mut s = OusterSource::open_udp(&config, &ctx()).expect("binds");
    std::thread::scope(|scope| {
        let h = scope.spawn(sender);
        let frames: Vec<LidarFrame> = std::iter::from_fn(|| s.next_frame())
            .map(|f| f.expect("frame"))
            .collect();
        let dropped = h.join().expect("sender");
        (frames, s.counters(), dropped)
    })
}

fn counter(c: &[(String, u64)], name: &str) -> u64 {
    c.iter().find(|(n, _)| n == name).map_or(0, |(_, v)| *v)
}

#[test]
fn live_frames_equal_the_captures() {
    in_netns("live_frames_equal_the_captures", || {
        let pcap = fixtures().join(format!("{SAMPLE}.pcap"));
        let (want, _) = pcap_frames(&pcap);
        assert_eq!(want.len(), 2);
        // Garbage among the packets: datagrams of other sizes are counted and skipped.
        let (got, counters, _) = live_frames(|| {
            let junk = UdpSocket::bind("127.0.0.1:0").expect("socket");
            for n in [1usize, 100, 1500] {
                junk.send_to(&vec![0xAB; n], ("127.0.0.1", PORT))
                    .expect("sends");
            }
            send(&pcap, 1.0, |_| false)
        });
        // The capture's last frame is incomplete: read from a file it is skipped (the end of
        // the capture), live it is handed on (a live stream has no end to tell).
        assert!(got.len() >= want.len(), "{} frames live", got.len());
        assert!(
            got[..want.len()] == want[..],
            "live frames differ from the capture's"
        );
        assert_eq!(counter(&counters, "datagrams_other_size"), 3);
        assert_eq!(counter(&counters, "packets_lost"), 0);
    });
}

#[test]
fn dropped_packets_leave_columns_invalid_and_are_counted() {
    in_netns(
        "dropped_packets_leave_columns_invalid_and_are_counted",
        || {
            let pcap = fixtures().join(format!("{SAMPLE}.pcap"));
            // 5 % of the lidar datagrams, every 20th from the 7th (the same ones in both).
            let lost = |i: usize| i % 20 == 7;
            let dir = tempfile::tempdir().expect("tempdir");
            let thinned = dir.path().join("thinned.pcap");
            let mut reader = PcapReader::new(File::open(&pcap).expect("capture")).expect("pcap");
            let mut writer =
                PcapWriter::with_header(File::create(&thinned).expect("file"), reader.header())
                    .expect("writer");
            let mut i = 0;
            while let Some(p) = reader.next_packet() {
                let p = p.expect("packet");
                // Ethernet (14) + IPv4 (20, no options in this capture) + UDP destination port.
                let port = u16::from_be_bytes([p.data[36], p.data[37]]);
                let keep = if port == 7502 {
                    i += 1;
                    !lost(i - 1)
                } else {
                    true
                };
                if keep {
                    writer
                        .write_packet(&PcapPacket::new(p.timestamp, p.orig_len, &p.data))
                        .expect("writes");
                }
            }
            drop(writer);
            let (want, want_counters) = pcap_frames(&thinned);
            let (got, counters, dropped) = live_frames(|| send(&pcap, 1.0, lost));
            assert!(dropped > 0);
            assert!(got.len() >= want.len() && !want.is_empty());
            assert!(
                got[..want.len()] == want[..],
                "live frames differ from the thinned capture's"
            );
            let lost_live = counter(&counters, "packets_lost");
            assert!(lost_live > 0, "no packet counted lost");
            assert!(
                lost_live >= counter(&want_counters, "packets_lost"),
                "live {lost_live}, capture {}",
                counter(&want_counters, "packets_lost")
            );
            // Frames with lost packets have invalid columns where the packets were.
            let invalid_columns = |f: &LidarFrame| {
                (0..f.cols)
                    .filter(|&c| (0..f.rows).all(|r| !f.valid[r * f.cols + c]))
                    .count()
            };
            assert!(got.iter().any(|f| invalid_columns(f) >= 16));
        },
    );
}
