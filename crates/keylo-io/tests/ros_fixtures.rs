//! The ROS fixtures (`tests/fixtures/ros/`, made from an OS-0-128 capture) read through source
//! kinds `ros1-bag` and `mcap` and `bag_info`, against rosbags' `golden.json`.

mod common;

use std::path::{Path, PathBuf};

use common::lit;

use keylo_core::{BuildContext, ImageSource, LidarFrame, Registry, ScanPoints};
use keylo_io::ros::{bag_info, BagFormat, BagSource, BagSourceConfig};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ros")
}

fn golden() -> Value {
    let text = std::fs::read_to_string(fixtures().join("golden.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// `(file name in golden.json, path to open, format)`.
fn files() -> [(&'static str, PathBuf, BagFormat); 3] {
    [
        (
            "ouster_ros1.bag",
            fixtures().join("ouster_ros1.bag"),
            BagFormat::Ros1Bag,
        ),
        (
            "ouster_ros2",
            fixtures().join("ouster_ros2"),
            BagFormat::Mcap,
        ),
        (
            "ouster_ros2",
            fixtures().join("ouster_ros2/ouster_ros2_0.mcap"),
            BagFormat::Mcap,
        ),
    ]
}

fn read(config: &BagSourceConfig, format: BagFormat) -> Vec<LidarFrame> {
    let mut source = BagSource::open(config, &BuildContext::default(), format).unwrap();
    std::iter::from_fn(|| source.next_frame())
        .map(Result::unwrap)
        .collect()
}

fn config(path: &Path, topic: &str) -> BagSourceConfig {
    BagSourceConfig {
        path: path.display().to_string(),
        topic: topic.into(),
        ..BagSourceConfig::default()
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

#[test]
fn info_lists_topics_counts_times_and_cloud_layouts() {
    let g = golden();
    for (name, path, format) in files() {
        let want = &g["files"][name];
        let info = bag_info(&path).unwrap();
        assert_eq!(info.format, format);
        assert_eq!((info.note.as_deref(), info.damage.as_deref()), (None, None));
        assert_eq!(info.start_ns, want["start_ns"].as_u64(), "{name}");
        assert_eq!(info.end_ns, want["end_ns"].as_u64(), "{name}");
        let topics = want["topics"].as_object().unwrap();
        assert_eq!(info.topics.len(), topics.len(), "{name}");
        for t in &info.topics {
            let w = &topics[&t.name];
            let ros1 = format == BagFormat::Ros1Bag;
            let ty = w["type"].as_str().unwrap();
            let ty = if ros1 {
                ty.replacen("/msg/", "/", 1)
            } else {
                ty.to_string()
            };
            assert_eq!(t.msg_type, ty, "{name} {}", t.name);
            assert_eq!(t.count, w["count"].as_u64(), "{name} {}", t.name);
            assert_eq!(t.encoding, if ros1 { "ros1" } else { "cdr" });
            let Some(c) = &t.cloud else { continue };
            let wc = &want["clouds"][&t.name];
            assert_eq!(u64::from(c.height), wc["height"].as_u64().unwrap());
            assert_eq!(u64::from(c.width), wc["width"].as_u64().unwrap());
            assert_eq!(u64::from(c.point_step), wc["point_step"].as_u64().unwrap());
            let fields: Vec<(String, u64)> = c
                .fields
                .iter()
                .map(|f| (f.name.clone(), u64::from(f.offset)))
                .collect();
            let wf: Vec<(String, u64)> = wc["fields"]
                .as_array()
                .unwrap()
                .iter()
                .map(|f| (f[0].as_str().unwrap().to_string(), f[1].as_u64().unwrap()))
                .collect();
            assert_eq!(fields, wf, "{name} {}", t.name);
            assert_eq!(c.stamp_ns, wc["frames"][0]["stamp_ns"].as_i64().unwrap());
        }
        let text = info.to_string();
        assert!(
            text.contains("/ouster/points") && text.contains("x@0:FLOAT32"),
            "{text}"
        );
    }
}

#[test]
fn organised_clouds_match_the_golden_sums() {
    let g = golden();
    for (name, path, format) in files() {
        let want = g["files"][name]["clouds"]["/ouster/points"]["frames"]
            .as_array()
            .unwrap()
            .clone();
        let frames = read(&config(&path, "/ouster/points"), format);
        assert_eq!(frames.len(), want.len(), "{name}");
        for (k, (f, w)) in frames.iter().zip(&want).enumerate() {
            let ctx = format!("{name} frame {k}");
            assert_eq!((f.index, f.rows, f.cols), (k as u64, 32, 1024), "{ctx}");
            let stamp = w["stamp_ns"].as_f64().unwrap() * 1e-9;
            assert!((f.timestamp - stamp).abs() < 1e-6, "{ctx}");
            assert_eq!(
                f.valid_count() as u64,
                w["valid"].as_u64().unwrap(),
                "{ctx}"
            );
            let sum = |g: &dyn Fn(usize) -> f64| {
                (0..f.valid.len())
                    .filter(|&i| f.valid[i])
                    .map(g)
                    .sum::<f64>()
            };
            for (axis, key) in ["sum_x", "sum_y", "sum_z"].iter().enumerate() {
                let s = sum(&|i| f64::from(f.points[i][axis]));
                assert!(close(s, w[key].as_f64().unwrap()), "{ctx} {key}: {s}");
            }
            let s = sum(&|i| f64::from(f.signal[i]));
            assert!(
                close(s, w["sum_intensity"].as_f64().unwrap()),
                "{ctx} intensity"
            );
            // ouster-ros `t` (u32 ns): the last column fires about 0.1 s after the stamp.
            let span = f.column_times.last().unwrap() - f.column_times[0];
            assert!(k == 0 || (0.09..0.1).contains(&span), "{ctx}: {span}");
            // Beams from the /ouster/metadata topic.
            assert_eq!(f.beams.model, "OS-0-128");
            assert_eq!(f.beams.altitude_deg.len(), 32);
            assert_eq!(f.beams.frame_rate_hz, 10.0);
        }
    }
}

#[test]
fn unorganised_clouds_are_projected_by_ring() {
    let g = golden();
    for (name, path, format) in files() {
        let want = g["files"][name]["clouds"]["/cloud_unorganised"]["frames"]
            .as_array()
            .unwrap()
            .clone();
        let mut c = config(&path, "/cloud_unorganised");
        c.projection.rows = Some(32);
        c.projection.cols = Some(1024);
        let frames = read(&c, format);
        let organised = read(&config(&path, "/ouster/points"), format);
        assert_eq!(frames.len(), 3);
        for ((f, w), o) in frames.iter().zip(&want).zip(&organised) {
            let map = f.scan.as_ref().unwrap();
            let points = w["points"].as_u64().unwrap() as usize;
            assert_eq!(map.len(), points, "{name}");
            assert_eq!(
                f.to_cloud().len(),
                points,
                "{name}: every point reaches the cloud"
            );
            assert!(map.pixel.iter().all(|&p| p != ScanPoints::NONE));
            // Nearly every point has a pixel of its own (ring rows, 1024 azimuth columns).
            assert!(
                f.valid_count() * 100 >= points * 90,
                "{name}: {} of {points}",
                f.valid_count()
            );
            // Ring r (row r of the organised cloud, top first) fills row r.
            let per_row = |f: &keylo_core::LidarFrame| -> Vec<usize> {
                (0..32)
                    .map(|r| (0..1024).filter(|&c| f.valid[r * 1024 + c]).count())
                    .collect()
            };
            let (p, q) = (per_row(f), per_row(o));
            assert!(
                p.iter()
                    .zip(&q)
                    .all(|(a, b)| a <= b && (*a > 0) == (*b > 0)),
                "{p:?} {q:?}"
            );
        }
    }
}

#[test]
fn image_topics_fill_channels_after_restaggering() {
    let path = fixtures().join("ouster_ros1.bag");
    let plain = read(&config(&path, "/ouster/points"), BagFormat::Ros1Bag);
    let mut c = config(&path, "/ouster/points");
    c.images.signal = "/ouster/signal_image".into();
    c.images.reflectivity = "/ouster/reflec_image".into();
    c.images.near_ir = "/ouster/nearir_image".into();
    c.images.range = "/ouster/range_image".into();
    for format_path in [path.clone(), fixtures().join("ouster_ros2")] {
        c.path = format_path.display().to_string();
        let format = if format_path == path {
            BagFormat::Ros1Bag
        } else {
            BagFormat::Mcap
        };
        let with = read(&c, format);
        assert_eq!(with.len(), plain.len());
        for (a, b) in with.iter().zip(&plain) {
            assert_eq!(a.signal, b.signal);
            assert_eq!(a.reflectivity, b.reflectivity);
            assert_eq!(a.near_ir, b.near_ir);
            for (i, (ra, rb)) in a.range.iter().zip(&b.range).enumerate() {
                assert!((ra - rb).abs() <= 0.0021, "pixel {i}: {ra} vs {rb}");
            }
            assert_eq!(a.valid, b.valid);
        }
    }
    // Taking the images as already staggered misplaces them.
    c.images.pixel_shift_by_row = vec![0];
    let wrong = read(&c, BagFormat::Mcap);
    assert_ne!(wrong[1].signal, plain[1].signal);
}

#[test]
fn start_stride_and_limit() {
    let g = golden();
    let path = fixtures().join("ouster_ros2");
    let c = BagSourceConfig {
        start: 1,
        stride: 1,
        max_frames: 1,
        ..config(&path, "/ouster/points")
    };
    let source = BagSource::open(&c, &BuildContext::default(), BagFormat::Mcap).unwrap();
    assert_eq!(source.info().frames, Some(1));
    let frames = read(&c, BagFormat::Mcap);
    assert_eq!(frames.len(), 1);
    assert_eq!(frames[0].index, 1);
    let stamp = g["files"]["ouster_ros2"]["clouds"]["/ouster/points"]["frames"][1]["stamp_ns"]
        .as_f64()
        .unwrap();
    assert!((frames[0].timestamp - stamp * 1e-9).abs() < 1e-6);
    let every_other = BagSourceConfig {
        stride: 2,
        ..config(&path, "/ouster/points")
    };
    let idx: Vec<u64> = read(&every_other, BagFormat::Mcap)
        .iter()
        .map(|f| f.index)
        .collect();
    assert_eq!(idx, vec![0, 2]);
}

#[test]
fn registered_kinds_and_data_probes() {
    let mut registry = Registry::default();
    keylo_io::register(&mut registry);
    let bag = fixtures().join("ouster_ros1.bag");
    let folder = fixtures().join("ouster_ros2");
    assert_eq!(registry.detect_source(&bag), Some("ros1-bag"));
    assert_eq!(registry.detect_source(&folder), Some("mcap"));
    assert_eq!(
        registry.detect_source(&folder.join("ouster_ros2_0.mcap")),
        Some("mcap")
    );
    assert_eq!(registry.detect_source(&fixtures()), None);
    let params = format!("path = {}\ntopic = \"/ouster/points\"", lit(&folder));
    let mut source = common::build("mcap", &params).unwrap();
    assert_eq!(source.info().frames, Some(3));
    assert!(source.next_frame().unwrap().is_ok());
    // The wrong kind for the file says which kind reads it.
    let err = common::build("ros1-bag", &params)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("source kind `mcap`"), "{err}");
}
