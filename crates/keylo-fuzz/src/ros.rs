//! ROS recordings (ROS1 bags, MCAP files) and the messages keylo decodes from them.

use std::sync::Arc;

use keylo_core::{BeamGeometry, BuildContext};
use keylo_io::cloud::organised::to_frame;
use keylo_io::cloud::{ProjectionConfig, Projector, Sensor};
use keylo_io::ros::{bag_info, to_raw_cloud, BagFormat, BagSource, BagSourceConfig, Encoding};
use keylo_io::ros::{decode_header, Image, ImageTopics, PointCloud2};

use crate::scratch;

/// A ROS1 bag: listed as `keylo info` does, then read as source kind `ros1-bag`.
pub fn ros1_bag(data: &[u8]) {
    recording(data, "capture.bag", BagFormat::Ros1Bag);
}

/// An MCAP file: listed as `keylo info` does, then read as source kind `mcap`.
pub fn mcap(data: &[u8]) {
    recording(data, "capture.mcap", BagFormat::Mcap);
}

/// A ROS 2 sqlite3 bag (`.db3`): listed as `keylo info` does, then read as source kind `mcap`
/// (which reads ROS 2 bags in either storage).
pub fn ros2_db3(data: &[u8]) {
    recording(data, "capture.db3", BagFormat::Mcap);
}

fn recording(data: &[u8], name: &str, format: BagFormat) {
    scratch::with_files(&[(name, data)], true, |dir| {
        let path = dir.join(name);
        let _ = bag_info(&path);
        let ctx = BuildContext {
            base_dir: dir.to_path_buf(),
            ..Default::default()
        };
        // The seeds' layout (ouster-ros topics, images beside a 2-row organised cloud), then
        // the defaults (the only cloud topic, no images).
        let images = ImageTopics {
            signal: "/ouster/signal_image".into(),
            range: "/ouster/range_image".into(),
            pixel_shift_by_row: vec![0; 2],
            ..ImageTopics::default()
        };
        let configs = [
            BagSourceConfig {
                path: name.into(),
                topic: "/ouster/points".into(),
                images,
                ..BagSourceConfig::default()
            },
            BagSourceConfig {
                path: name.into(),
                ..BagSourceConfig::default()
            },
        ];
        for config in &configs {
            if let Ok(mut source) = BagSource::open(config, &ctx, format) {
                crate::drain(&mut source);
            }
        }
    });
}

/// One serialised message after a selector byte: bit 0 picks the encoding (ROS1, CDR),
/// bit 1 the type (`sensor_msgs/PointCloud2`, `sensor_msgs/Image`). A cloud is turned into
/// a frame as the bag sources do (pixel for pixel when organised, else projected).
pub fn ros_messages(data: &[u8]) {
    let Some((&selector, msg)) = data.split_first() else {
        return;
    };
    let encoding = if selector & 1 == 0 {
        Encoding::Ros1
    } else {
        Encoding::Cdr
    };
    let _ = decode_header(msg, encoding);
    if selector & 2 != 0 {
        let _ = Image::decode(msg, encoding);
        return;
    }
    let Ok(cloud) = PointCloud2::decode(msg, encoding) else {
        return;
    };
    let Ok(raw) = to_raw_cloud(&cloud) else {
        return;
    };
    if raw.check().is_err() {
        return;
    }
    if let Some((rows, cols)) = raw.grid {
        let beams = Arc::new(BeamGeometry::unknown("fuzz", cols));
        crate::check_frame(&to_frame(&raw, rows, cols, 0, beams));
    } else if let Ok(mut projector) =
        Projector::from_config(&ProjectionConfig::default(), Sensor::Generic)
    {
        if let Ok(frame) = projector.project(&raw, 0) {
            crate::check_frame(&frame);
        }
    }
}
