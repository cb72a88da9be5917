//! The ROS2 sqlite3 fixture (`tests/fixtures/ros/ouster_ros2_db3/`, the MCAP fixture's messages
//! copied byte for byte by `make_db3_fixture.py`) read through source kind `mcap`: the same
//! frames as the MCAP bag, topic choice, `bag_info`, `--data` detection, and damaged copies.

mod common;

use std::path::{Path, PathBuf};

use common::lit;

use keylo_core::{BuildContext, ImageSource, LidarFrame, Registry};
use keylo_io::ros::{bag_info, BagFormat, BagSource, BagSourceConfig};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ros")
}

fn db3_folder() -> PathBuf {
    fixtures().join("ouster_ros2_db3")
}

fn db3_file() -> PathBuf {
    db3_folder().join("ouster_ros2_db3.db3")
}

fn mcap_folder() -> PathBuf {
    fixtures().join("ouster_ros2")
}

fn config(path: &Path, topic: &str) -> BagSourceConfig {
    BagSourceConfig {
        path: path.display().to_string(),
        topic: topic.into(),
        ..BagSourceConfig::default()
    }
}

fn open(config: &BagSourceConfig) -> Result<BagSource, String> {
    BagSource::open(config, &BuildContext::default(), BagFormat::Mcap).map_err(|e| e.to_string())
}

fn read(config: &BagSourceConfig) -> Vec<LidarFrame> {
    let mut source = open(config).unwrap();
    std::iter::from_fn(|| source.next_frame())
        .map(Result::unwrap)
        .collect()
}

/// Frames compare bit for bit (`Debug` prints every float exactly, NaN included).
fn assert_same(a: &[LidarFrame], b: &[LidarFrame], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            format!("{x:?}") == format!("{y:?}"),
            "{what}: frame {k} differs"
        );
    }
}

#[test]
fn unorganised_clouds_equal_the_mcap_bags() {
    for path in [db3_folder(), db3_file()] {
        let mut c = config(&path, "/cloud_unorganised");
        c.projection.rows = Some(32);
        c.projection.cols = Some(1024);
        let db3 = read(&c);
        c.path = mcap_folder().display().to_string();
        let mcap = read(&c);
        assert_eq!(db3.len(), 3);
        assert_same(&db3, &mcap, &path.display().to_string());
    }
}

#[test]
fn organised_clouds_with_metadata_and_images_equal_the_mcap_bags() {
    // The db3 bag keeps the second cloud and its signal image (see make_db3_fixture.py).
    let mut c = config(&db3_folder(), "/ouster/points");
    c.images.signal = "/ouster/signal_image".into();
    let db3 = read(&c);
    c.path = mcap_folder().display().to_string();
    c.start = 1;
    c.max_frames = 1;
    let mut mcap = read(&c);
    assert_eq!((db3.len(), mcap.len()), (1, 1));
    assert_eq!(mcap[0].index, 1);
    mcap[0].index = 0;
    assert_same(&db3, &mcap, "organised");
    let f = &db3[0];
    // Per-point times (ouster-ros `t`), beams from /ouster/metadata, the image's signal.
    let span = f.column_times.last().unwrap() - f.column_times[0];
    assert!((0.09..0.1).contains(&span), "{span}");
    assert_eq!(
        (f.beams.model.as_str(), f.beams.altitude_deg.len()),
        ("OS-0-128", 32)
    );
    // The fixture's image holds the raw signal: restaggered with the metadata's shifts it is
    // the cloud's intensity field; taken as staggered it is misplaced, so it was read.
    let plain = read(&config(&db3_file(), "/ouster/points"));
    assert!(plain[0].signal == f.signal && plain[0].points == f.points);
    c.path = db3_folder().display().to_string();
    (c.start, c.max_frames) = (0, 0);
    c.images.pixel_shift_by_row = vec![0];
    assert!(read(&c)[0].signal != f.signal);
}

#[test]
fn the_topic_is_chosen_and_a_missing_one_is_named() {
    let e = open(&config(&db3_folder(), "")).err().unwrap();
    assert!(
        e.contains("ouster_ros2_db3.db3")
            && e.contains("2 sensor_msgs/PointCloud2 topics")
            && e.contains("/cloud_unorganised (sensor_msgs/msg/PointCloud2, 3 messages)")
            && e.contains("/ouster/points (sensor_msgs/msg/PointCloud2, 1 messages)"),
        "{e}"
    );
    let e = open(&config(&db3_file(), "/ouster/nope")).err().unwrap();
    assert!(
        e.contains("ouster_ros2_db3.db3") && e.contains("no topic `/ouster/nope`"),
        "{e}"
    );
    let source = open(&config(&db3_folder(), "/cloud_unorganised")).unwrap();
    let info = source.info();
    assert_eq!(info.frames, Some(3));
    assert!(info
        .description
        .contains("ouster_ros2_db3.db3 topic /cloud_unorganised"));
}

#[test]
fn info_lists_the_topics_as_the_mcap_bag_has_them() {
    let db3 = bag_info(&db3_folder()).unwrap();
    let mcap = bag_info(&mcap_folder()).unwrap();
    assert_eq!(db3.format, BagFormat::Ros2Sqlite3);
    assert_eq!(db3.path, db3_file());
    assert_eq!((db3.note.as_deref(), db3.damage.as_deref()), (None, None));
    assert_eq!((db3.start_ns, db3.end_ns), (mcap.start_ns, mcap.end_ns));
    let listed: Vec<(&str, &str, &str, Option<u64>)> = db3
        .topics
        .iter()
        .map(|t| {
            (
                t.name.as_str(),
                t.msg_type.as_str(),
                t.encoding.as_str(),
                t.count,
            )
        })
        .collect();
    assert_eq!(
        listed,
        [
            (
                "/cloud_unorganised",
                "sensor_msgs/msg/PointCloud2",
                "cdr",
                Some(3)
            ),
            ("/ouster/metadata", "std_msgs/msg/String", "cdr", Some(1)),
            (
                "/ouster/points",
                "sensor_msgs/msg/PointCloud2",
                "cdr",
                Some(1)
            ),
            (
                "/ouster/signal_image",
                "sensor_msgs/msg/Image",
                "cdr",
                Some(1)
            ),
        ]
    );
    let layout = |info: &keylo_io::ros::BagInfo, topic: &str| {
        let t = info.topics.iter().find(|t| t.name == topic).unwrap();
        let mut c = t.cloud.clone().unwrap();
        c.stamp_ns = 0; // the db3 bag's first /ouster/points is the MCAP bag's second
        c
    };
    for topic in ["/cloud_unorganised", "/ouster/points"] {
        assert_eq!(layout(&db3, topic), layout(&mcap, topic), "{topic}");
    }
    let text = db3.to_string();
    assert!(
        text.contains("/ouster/points  sensor_msgs/msg/PointCloud2  [cdr]  1 messages")
            && text.contains("x@0:FLOAT32"),
        "{text}"
    );
    // `keylo info` shows the source's details.
    let source = open(&config(&db3_file(), "/ouster/points")).unwrap();
    let details = source.details();
    assert!(
        details
            .iter()
            .any(|(k, v)| k == "topic /cloud_unorganised" && v.contains("3 messages")),
        "{details:?}"
    );
}

#[test]
fn data_paths_are_detected_as_kind_mcap() {
    let mut registry = Registry::default();
    keylo_io::register(&mut registry);
    assert_eq!(registry.detect_source(&db3_folder()), Some("mcap"));
    assert_eq!(registry.detect_source(&db3_file()), Some("mcap"));
    let params = format!(
        "path = {}\ntopic = \"/cloud_unorganised\"",
        lit(&db3_folder())
    );
    let mut source = common::build("mcap", &params).unwrap();
    assert_eq!(source.info().frames, Some(3));
    assert!(source.next_frame().unwrap().is_ok());
    let err = common::build("ros1-bag", &params)
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("ROS2 sqlite3 bag") && err.contains("source kind `mcap`"),
        "{err}"
    );
}
