//! Damaged copies of the ROS fixtures: the frames before the damage are read, then one error
//! names the file, the place (byte offset, message index) and what was wrong; never a panic.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_mentions, read_until_error, temp_file as write};
use keylo_core::{BuildContext, ImageSource};
use keylo_io::ros::{bag_info, BagFormat, BagSource, BagSourceConfig};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ros")
}

/// Byte offsets of the chunks holding the three /ouster/points messages.
fn points_chunks(name: &str) -> Vec<usize> {
    let text = std::fs::read_to_string(fixtures().join("golden.json")).unwrap();
    let g: Value = serde_json::from_str(&text).unwrap();
    g["files"][name]["points_chunks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap() as usize)
        .collect()
}

fn bag_bytes() -> Vec<u8> {
    std::fs::read(fixtures().join("ouster_ros1.bag")).unwrap()
}

fn mcap_bytes() -> Vec<u8> {
    std::fs::read(fixtures().join("ouster_ros2/ouster_ros2_0.mcap")).unwrap()
}

/// Reads /ouster/points: the frames read, then the error text (if any).
fn read(path: &Path, format: BagFormat) -> (usize, Option<String>) {
    let config = BagSourceConfig {
        path: path.display().to_string(),
        topic: "/ouster/points".into(),
        ..BagSourceConfig::default()
    };
    let mut source = BagSource::open(&config, &BuildContext::default(), format).unwrap();
    read_until_error(&mut source)
}

#[test]
fn corrupt_bag_chunk() {
    let mut bytes = bag_bytes();
    let third = points_chunks("ouster_ros1.bag")[2];
    // The chunk's compressed data starts about 50 bytes in; damage its first records.
    for b in &mut bytes[third + 70..third + 110] {
        *b ^= 0x5a;
    }
    let (_d, path) = write("corrupt.bag", &bytes);
    let (ok, err) = read(&path, BagFormat::Ros1Bag);
    assert_eq!(ok, 2);
    let err = err.expect("an error after two frames");
    assert_mentions(
        &err,
        &[
            "corrupt.bag",
            &format!("chunk at byte {third}"),
            "/ouster/points message 2",
        ],
    );
}

#[test]
fn bag_chunk_claiming_4_gib() {
    let mut bytes = bag_bytes();
    let third = points_chunks("ouster_ros1.bag")[2];
    // The chunk header's `size=` field: its declared uncompressed size.
    let at = third
        + bytes[third..third + 100]
            .windows(5)
            .position(|w| w == b"size=")
            .expect("size field in the chunk header")
        + 5;
    bytes[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    let (_d, path) = write("claim.bag", &bytes);
    let (ok, err) = read(&path, BagFormat::Ros1Bag);
    assert_eq!(ok, 2);
    let err = err.expect("an error after two frames");
    assert_mentions(
        &err,
        &[
            "claim.bag",
            &format!("chunk at byte {third}"),
            "4294967295 bytes uncompressed, over the 512 MiB chunk limit",
        ],
    );
}

#[test]
fn truncated_bag() {
    let bytes = bag_bytes();
    let third = points_chunks("ouster_ros1.bag")[2];
    let (_d, path) = write("cut.bag", &bytes[..third + 1000]);
    let info = bag_info(&path).unwrap();
    assert!(
        info.note.as_deref().unwrap().contains("no index"),
        "{info:?}"
    );
    let (ok, err) = read(&path, BagFormat::Ros1Bag);
    assert_eq!(ok, 2);
    let err = err.expect("an error after two frames");
    assert_mentions(
        &err,
        &[
            "cut.bag",
            &format!("record at byte {third}"),
            "messages before it were read",
        ],
    );
}

#[test]
fn mcap_with_a_bad_chunk_crc() {
    let mut bytes = mcap_bytes();
    let third = points_chunks("ouster_ros2")[2];
    // Chunk record: opcode, length (8), start and end time, uncompressed size (8 each), CRC.
    bytes[third + 33] ^= 0xff;
    let (_d, path) = write("crc.mcap", &bytes);
    let (ok, err) = read(&path, BagFormat::Mcap);
    assert_eq!(ok, 2);
    let err = err.expect("an error after two frames");
    assert_mentions(
        &err,
        &["crc.mcap", &format!("chunk at byte {third}"), "message 2"],
    );
    assert!(err.to_lowercase().contains("crc"), "{err}");
}

#[test]
fn truncated_mcap() {
    let bytes = mcap_bytes();
    let third = points_chunks("ouster_ros2")[2];
    let (_d, path) = write("cut.mcap", &bytes[..third + 1000]);
    let (ok, err) = read(&path, BagFormat::Mcap);
    assert_eq!(ok, 2);
    let err = err.expect("an error after two frames");
    assert_mentions(
        &err,
        &[
            "cut.mcap",
            "near byte",
            "message 2",
            "messages before it were read",
        ],
    );
    let info = bag_info(&path).unwrap();
    assert!(info.note.unwrap().contains("summary"));
    assert!(info.damage.is_some());
}

#[test]
fn cut_anywhere_never_panics() {
    for (name, bytes, format) in [
        ("x.bag", bag_bytes(), BagFormat::Ros1Bag),
        ("x.mcap", mcap_bytes(), BagFormat::Mcap),
    ] {
        for cut in [
            0,
            5,
            13,
            20,
            100,
            4096,
            4200,
            100_000,
            bytes.len() / 2,
            bytes.len() - 9,
        ] {
            let (_d, path) = write(name, &bytes[..cut]);
            let _ = bag_info(&path);
            let config = BagSourceConfig {
                path: path.display().to_string(),
                ..BagSourceConfig::default()
            };
            if let Ok(mut s) = BagSource::open(&config, &BuildContext::default(), format) {
                while let Some(Ok(_)) = s.next_frame() {}
            }
        }
    }
}

#[test]
fn missing_topics_list_the_candidates() {
    let path = fixtures().join("ouster_ros1.bag");
    let open = |topic: &str| {
        let c = BagSourceConfig {
            path: path.display().to_string(),
            topic: topic.into(),
            ..BagSourceConfig::default()
        };
        BagSource::open(&c, &BuildContext::default(), BagFormat::Ros1Bag)
            .err()
            .unwrap()
            .to_string()
    };
    let err = open("");
    assert_mentions(
        &err,
        &[
            "ouster_ros1.bag",
            "set `source.topic` to one of:",
            "/ouster/points (sensor_msgs/PointCloud2, 3 messages)",
            "/cloud_unorganised (sensor_msgs/PointCloud2, 3 messages)",
        ],
    );
    assert_mentions(
        &open("/velodyne_points"),
        &["no topic `/velodyne_points`", "/ouster/points ("],
    );
    let c = BagSourceConfig {
        path: path.display().to_string(),
        topic: "/ouster/points".into(),
        images: keylo_io::ros::ImageTopics {
            signal: "/ouster/signal".into(),
            ..Default::default()
        },
        ..BagSourceConfig::default()
    };
    let err = BagSource::open(&c, &BuildContext::default(), BagFormat::Ros1Bag)
        .err()
        .unwrap()
        .to_string();
    assert_mentions(&err, &["source.images.signal", "/ouster/signal_image ("]);
}

/// Bytes flipped at pseudo-random places (a fixed LCG, so the test is repeatable): reading
/// every topic ends with frames or an error, never a panic.
#[test]
fn flipped_bytes_never_panic() {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |n: usize| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 33) as usize % n
    };
    let rounds: usize = std::env::var("KEYLO_FLIP_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(24);
    for (name, original, format) in [
        ("x.bag", bag_bytes(), BagFormat::Ros1Bag),
        ("x.mcap", mcap_bytes(), BagFormat::Mcap),
    ] {
        for _ in 0..rounds {
            let mut bytes = original.clone();
            let at = next(bytes.len() - 64);
            for k in 0..1 + next(32) {
                bytes[at + k] ^= 1 + next(255) as u8;
            }
            let (_d, path) = write(name, &bytes);
            let _ = bag_info(&path);
            for topic in ["/ouster/points", "/cloud_unorganised"] {
                let mut config = BagSourceConfig {
                    path: path.display().to_string(),
                    topic: topic.into(),
                    ..BagSourceConfig::default()
                };
                config.images.signal = "/ouster/signal_image".into();
                if topic == "/cloud_unorganised" {
                    config.images.signal.clear();
                }
                if let Ok(mut s) = BagSource::open(&config, &BuildContext::default(), format) {
                    while let Some(Ok(_)) = s.next_frame() {}
                }
            }
        }
    }
}
