//! Real Ouster frames for the feature tests (the BSD-3 samples in tests/fixtures/ouster).
#![allow(dead_code)]

use std::path::PathBuf;

use keylo_core::{BuildContext, Image, ImageBuilder, ImageSource, LidarFrame};
use keylo_features::image::{LidarImageBuilder, LidarImageConfig};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};

/// The workspace's `tests/fixtures/ouster/` folder.
pub fn ouster_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ouster")
}

/// Every complete frame of the OS-0-128 sample (1024×128, signal images).
pub fn os0_frames() -> Vec<LidarFrame> {
    let config = OusterSourceConfig {
        path: ouster_dir()
            .join("OS-0-128_v3.0.1_1024x10_from_osf.pcap")
            .display()
            .to_string(),
        ..OusterSourceConfig::default()
    };
    let mut source = OusterSource::open(&config, &BuildContext::default()).expect("open sample");
    let mut frames = Vec::new();
    while let Some(f) = source.next_frame() {
        frames.push(f.expect("frame"));
    }
    assert!(!frames.is_empty());
    frames
}

/// The images of `frame` made with `config`.
pub fn images(frame: &LidarFrame, config: LidarImageConfig) -> Vec<Image> {
    LidarImageBuilder::new(config)
        .expect("image config")
        .build(frame)
        .expect("images")
}

/// The default 1024×64 linear signal image of `frame`.
pub fn signal_image(frame: &LidarFrame) -> Image {
    images(frame, LidarImageConfig::default()).remove(0)
}
