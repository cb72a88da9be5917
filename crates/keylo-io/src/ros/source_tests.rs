use std::collections::BTreeMap;
use std::io::Cursor;

use keylo_core::{BuildContext, ImageSource};
use mcap::records::MessageHeader;

use super::*;
use crate::ros::msgs::tests::{cloud_msg, Writer};

/// An mcap of `(topic, type, log_time, CDR payload)` messages.
fn write_mcap(msgs: &[(&str, &str, u64, Vec<u8>)]) -> (tempfile::TempDir, std::path::PathBuf) {
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    let mut channels: BTreeMap<String, u16> = BTreeMap::new();
    for (i, (topic, ty, t, data)) in msgs.iter().enumerate() {
        let id = match channels.get(*topic) {
            Some(id) => *id,
            None => {
                let schema = w.add_schema(ty, "ros2msg", b"").unwrap();
                let id = w
                    .add_channel(schema, topic, "cdr", &BTreeMap::new())
                    .unwrap();
                channels.insert(topic.to_string(), id);
                id
            }
        };
        let header = MessageHeader {
            channel_id: id,
            sequence: i as u32,
            log_time: *t,
            publish_time: *t,
        };
        w.write_to_known_channel(&header, data).unwrap();
    }
    w.finish().unwrap();
    let bytes = w.into_inner().into_inner();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("test.mcap");
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

const PC2: &str = "sensor_msgs/msg/PointCloud2";
const XYZ: [(&str, u32, u8); 3] = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7)];

/// A 2×2 organised cloud stamped `stamp` (points 1 m ahead).
fn organised(stamp: i64) -> Vec<u8> {
    let mut data = Vec::new();
    for _ in 0..4 {
        data.extend(1f32.to_le_bytes());
        data.extend([0u8; 8]);
    }
    cloud_msg(Encoding::Cdr, stamp, (2, 2, 12), &XYZ, false, &data)
}

fn image(stamp: i64, value: u8) -> Vec<u8> {
    let mut w = Writer::new(Encoding::Cdr);
    w.header(stamp)
        .u32(2)
        .u32(2)
        .string("mono8")
        .u8(0)
        .u32(2)
        .bytes(&[value; 4]);
    w.buf
}

fn open(path: &std::path::Path, edit: impl Fn(&mut BagSourceConfig)) -> Result<BagSource, String> {
    let mut c = BagSourceConfig {
        path: path.display().to_string(),
        ..BagSourceConfig::default()
    };
    edit(&mut c);
    BagSource::open(&c, &BuildContext::default(), BagFormat::Mcap).map_err(|e| e.to_string())
}

fn frames(s: &mut BagSource) -> Vec<Result<LidarFrame, String>> {
    std::iter::from_fn(|| s.next_frame())
        .map(|r| r.map_err(|e| e.to_string()))
        .collect()
}

#[test]
fn bad_clouds_name_file_message_and_problem() {
    let short = cloud_msg(Encoding::Cdr, 3, (2, 2, 12), &XYZ, false, &[0u8; 40]);
    let no_z = cloud_msg(Encoding::Cdr, 4, (1, 1, 8), &XYZ[..2], false, &[0u8; 8]);
    for (bad, want) in [
        (
            short,
            "data holds 40 bytes but height × row_step = 2 × 24 = 48",
        ),
        (no_z, "no `z` field"),
    ] {
        let (_d, path) = write_mcap(&[("/p", PC2, 1, organised(1)), ("/p", PC2, 2, bad)]);
        let mut s = open(&path, |_| {}).unwrap();
        let got = frames(&mut s);
        assert!(got[0].is_ok());
        let e = got[1].as_ref().unwrap_err();
        for part in ["test.mcap", "/p message 1", "log time 2 ns", want] {
            assert!(e.contains(part), "`{part}` missing: {e}");
        }
        assert_eq!(got.len(), 2);
    }
}

#[test]
fn images_match_by_stamp_in_either_order() {
    let (_d, path) = write_mcap(&[
        ("/img", "sensor_msgs/msg/Image", 5, image(10, 7)), // image before its cloud
        ("/p", PC2, 6, organised(10)),
        ("/p", PC2, 7, organised(20)),
        ("/img", "sensor_msgs/msg/Image", 8, image(20, 9)), // after it
    ]);
    let mut s = open(&path, |c| {
        c.images.reflectivity = "/img".into();
        c.images.pixel_shift_by_row = vec![0];
    })
    .unwrap();
    let got: Vec<LidarFrame> = frames(&mut s).into_iter().map(Result::unwrap).collect();
    assert_eq!(got[0].reflectivity, vec![7.0; 4]);
    assert_eq!(got[1].reflectivity, vec![9.0; 4]);
}

#[test]
fn unmatched_images_are_errors() {
    let (_d, path) = write_mcap(&[
        ("/p", PC2, 6, organised(10)),
        ("/img", "sensor_msgs/msg/Image", 7, image(11, 7)),
    ]);
    let mut s = open(&path, |c| {
        c.images.signal = "/img".into();
        c.images.pixel_shift_by_row = vec![0];
    })
    .unwrap();
    let e = frames(&mut s)[0].clone().unwrap_err();
    assert!(
        e.contains("no /img image stamped 10 ns") && e.contains("next one is stamped 11"),
        "{e}"
    );

    // Without point times, the image shift must be given.
    let (_d, path) = write_mcap(&[
        ("/p", PC2, 6, organised(10)),
        ("/img", "sensor_msgs/msg/Image", 7, image(10, 7)),
    ]);
    let mut s = open(&path, |c| c.images.signal = "/img".into()).unwrap();
    let e = frames(&mut s)[0].clone().unwrap_err();
    assert!(e.contains("pixel_shift_by_row"), "{e}");
}

#[test]
fn images_need_organised_clouds_and_a_known_topic() {
    let flat = cloud_msg(Encoding::Cdr, 10, (1, 1, 12), &XYZ, false, &[0u8; 12]);
    let (_d, path) = write_mcap(&[
        ("/p", PC2, 6, flat),
        ("/img", "sensor_msgs/msg/Image", 7, image(10, 7)),
    ]);
    let mut s = open(&path, |c| c.images.signal = "/img".into()).unwrap();
    let e = frames(&mut s)[0].clone().unwrap_err();
    assert!(e.contains("organised clouds only"), "{e}");
    let e = open(&path, |c| c.images.signal = "/p".into())
        .err()
        .unwrap();
    assert!(
        e.contains("holds sensor_msgs/msg/PointCloud2, expected sensor_msgs/Image"),
        "{e}"
    );
}

#[test]
fn bad_metadata_and_selection_errors() {
    let mut w = Writer::new(Encoding::Cdr);
    w.string("{not json");
    let (_d, path) = write_mcap(&[
        ("/ouster/metadata", "std_msgs/msg/String", 1, w.buf),
        ("/p", PC2, 6, organised(10)),
    ]);
    let e = open(&path, |_| {}).err().unwrap();
    assert!(
        e.contains("/ouster/metadata") && e.contains("metadata_topic = \"\""),
        "{e}"
    );
    assert!(open(&path, |c| c.metadata_topic.clear()).is_ok());
    let e = open(&path, |c| {
        c.metadata_topic.clear();
        c.start = 5;
    })
    .err()
    .unwrap();
    assert!(
        e.contains("source.start") && e.contains("holds 1 frames"),
        "{e}"
    );
    let e = open(&path, |c| {
        c.metadata_topic.clear();
        c.projection.cols = Some(0);
    })
    .err()
    .unwrap();
    assert!(e.contains("source.projection.cols"), "{e}");
    let e = open(&path, |c| c.path.clear()).err().unwrap();
    assert!(e.contains("source.path"), "{e}");
}
