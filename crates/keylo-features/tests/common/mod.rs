//! Real Ouster frames for the feature tests (the BSD-3 samples in tests/fixtures/ouster).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use keylo_core::{BuildContext, Channel, Image, ImageBuilder, ImageSource, LidarFrame};
use keylo_features::image::{resize_plane, Interpolation, LidarImageBuilder, LidarImageConfig};
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

/// The workspace root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An 8-bit grey PNG: (pixels, rows, cols).
pub fn read_png(path: &Path) -> (Vec<u8>, usize, usize) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(
        info.color_type,
        png::ColorType::Grayscale,
        "{}",
        path.display()
    );
    buf.truncate(info.buffer_size());
    (buf, info.height as usize, info.width as usize)
}

/// A read PNG resized (linear, as the paper) to `width × height`.
pub fn resized((data, rows, cols): &(Vec<u8>, usize, usize), width: usize, height: usize) -> Image {
    let mut img = Image::new_gray(width, height, Channel::Signal);
    img.data = resize_plane(data, *rows, *cols, width, height, Interpolation::Linear).unwrap();
    img
}

/// A grey PNG at the paper's 1024×64 (linear).
pub fn png_image(path: &Path) -> Image {
    resized(&read_png(path), 1024, 64)
}
