//! Times detect (+ describe) per detector/descriptor combination on real 1024×64 LiDAR
//! signal images, for `scripts/bench/detect_vs_opencv_python.sh`.
//!
//! Usage: detect_timing IMAGE_DIR REPEATS INPUT...
//! Each INPUT is a PCAP, whose every frame's signal image the default `lidar` image builder
//! makes (1024×64, linear), or `DIR:COUNT`, the first COUNT `image_NNNN.png` of DIR (the
//! paper's images) resized to 1024×64 (linear). The images are written to IMAGE_DIR as PNG (the
//! Python side reads the same files), then one JSON object is printed: milliseconds per image
//! for each combination.

#[path = "common/images.rs"]
mod images;

use std::io::BufWriter;
use std::path::Path;
use std::time::Instant;

use keylo_core::{BuildContext, Descriptor, Detector, ImageBuilder, ImageSource, Registry};
use keylo_features::image::{LidarImageBuilder, LidarImageConfig};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};

/// (name, detector kind, detector params, descriptor kind or "" — descriptors at defaults).
/// Parameters are OpenCV's defaults except where the paper changed them (FAST threshold 30,
/// GFTT block size 4 / min distance 4 / max corners rows·cols/4).
pub const COMBOS: [(&str, &str, &str, &str); 11] = [
    (
        "shi-tomasi",
        "shi-tomasi",
        "block_size = 4\nmin_distance = 4.0\nmax_corners = 16384",
        "",
    ),
    (
        "harris",
        "harris",
        "block_size = 4\nmin_distance = 4.0\nmax_corners = 16384",
        "",
    ),
    ("fast", "fast", "threshold = 30", ""),
    ("fast_orb", "fast", "threshold = 30", "orb"),
    (
        "shi-tomasi_sift",
        "shi-tomasi",
        "block_size = 4\nmin_distance = 4.0\nmax_corners = 16384",
        "sift",
    ),
    ("akaze_akaze", "akaze", "describe = true", ""),
    ("orb_orb", "orb", "describe = true", ""),
    ("brisk_brisk", "brisk", "describe = true", ""),
    ("sift_sift", "sift", "describe = true", ""),
    ("kaze_kaze", "kaze", "describe = true", ""),
    ("fast_brisk", "fast", "threshold = 30", "brisk"),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // As the `keylo` binary does (see keep_native_heap).
    keylo_features::keep_native_heap();
    let args: Vec<String> = std::env::args().collect();
    let (out, repeats, pcaps) = match args.as_slice() {
        [_, o, r, pcaps @ ..] if !pcaps.is_empty() => {
            (std::path::PathBuf::from(o), r.parse::<usize>()?, pcaps)
        }
        _ => return Err("usage: detect_timing IMAGE_DIR REPEATS INPUT...".into()),
    };
    let mut builder = LidarImageBuilder::new(LidarImageConfig::default())?;
    let mut images = Vec::new();
    for pcap in pcaps {
        if let Some((dir, count)) = pcap.rsplit_once(':') {
            images.extend(images::load(Path::new(dir), count.parse()?, (1024, 64))?);
            continue;
        }
        let config = OusterSourceConfig {
            path: pcap.clone(),
            ..OusterSourceConfig::default()
        };
        let mut source = OusterSource::open(&config, &BuildContext::default())?;
        while let Some(frame) = source.next_frame() {
            images.extend(builder.build(&frame?)?);
        }
    }
    std::fs::create_dir_all(&out)?;
    for (i, img) in images.iter().enumerate() {
        let file = std::fs::File::create(out.join(format!("signal_{i:02}.png")))?;
        let mut enc = png::Encoder::new(BufWriter::new(file), img.width as u32, img.height as u32);
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header()?.write_image_data(&img.data)?;
    }
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let ctx = BuildContext::default();
    let mut result = serde_json::Map::new();
    let mut counts = serde_json::Map::new();
    for (name, det_kind, det_params, desc_kind) in COMBOS {
        let f = registry.detectors.get(det_kind).ok_or("detector")?;
        let mut det: Box<dyn Detector> =
            f.build(&f.resolve(&det_params.parse()?).map_err(|e| e.1)?, &ctx)?;
        let mut desc: Option<Box<dyn Descriptor>> = match desc_kind {
            "" => None,
            kind => {
                let f = registry.descriptors.get(kind).ok_or("descriptor")?;
                Some(f.build(&f.resolve(&toml::Table::new()).map_err(|e| e.1)?, &ctx)?)
            }
        };
        let mut keypoints = 0usize;
        let t = Instant::now();
        for _ in 0..repeats {
            for img in &images {
                let (mut kps, _) = det.detect_and_describe(img)?;
                if let Some(d) = desc.as_mut() {
                    d.describe(img, &mut kps)?;
                }
                keypoints += kps.len();
            }
        }
        let n = (repeats * images.len()) as f64;
        result.insert(name.into(), (t.elapsed().as_secs_f64() * 1e3 / n).into());
        counts.insert(name.into(), (keypoints as f64 / n).into());
    }
    let json = serde_json::json!({
        "tool": "keylo",
        "images": images.len(),
        "ms_per_image": result,
        "keypoints_per_image": counts,
    });
    println!("{json}");
    Ok(())
}
