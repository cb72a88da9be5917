//! AKAZE detect + describe per image, on one thread: OpenCV's AKAZE at its defaults (every
//! scale level built) against keylo's `akaze` (only the levels the image size can use), on
//! the same images in one run, interleaved; prints milliseconds per image, the ratio, and on
//! how many images the keypoints and descriptors are identical, as JSON.
//! `scripts/bench/akaze_levels.sh` runs it on the paper's real images.
//!
//! Usage: akaze_timing IMAGE_DIR [COUNT] [WIDTH HEIGHT]
//! (IMAGE_DIR: 8-bit grey PNGs `image_0000.png`…, resized linearly to WIDTH×HEIGHT, default
//! 1024×64, the paper's size.)

#[path = "common/images.rs"]
mod images;

use std::path::Path;
use std::time::Instant;

use keylo_core::{Detector, Registry};
use keylo_features::classic::{AkazeParams, CvFeature};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // As the `keylo` binary does (see keep_native_heap).
    keylo_features::keep_native_heap();
    opencv::core::set_num_threads(1)?;
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: akaze_timing IMAGE_DIR [COUNT] [WIDTH HEIGHT]";
    let dir = Path::new(args.get(1).ok_or(usage)?);
    let count: usize = args.get(2).map_or(Ok(200), |s| s.parse())?;
    let width: usize = args.get(3).map_or(Ok(1024), |s| s.parse())?;
    let height: usize = args.get(4).map_or(Ok(64), |s| s.parse())?;
    let images = images::load(dir, count, (width, height))?;
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let f = registry.detectors.get("akaze").ok_or("no akaze detector")?;
    let mut keylo: Box<dyn Detector> = f.build(
        &f.resolve(&"describe = true".parse()?).map_err(|e| e.1)?,
        &Default::default(),
    )?;
    let mut opencv = CvFeature::new(&AkazeParams {
        describe: true,
        ..AkazeParams::default()
    })?;
    let (mut t_keylo, mut t_opencv, mut identical, mut keypoints) = (0.0, 0.0, 0, 0);
    for img in &images {
        let t = Instant::now();
        let want = Detector::detect_and_describe(&mut opencv, img)?;
        t_opencv += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let got = keylo.detect_and_describe(img)?;
        t_keylo += t.elapsed().as_secs_f64();
        keypoints += want.0.len();
        identical += usize::from(got == want);
    }
    let n = images.len().max(1) as f64;
    println!(
        "{}",
        serde_json::json!({
            "images": images.len(),
            "size": format!("{width}x{height}"),
            "keypoints_per_image": keypoints as f64 / n,
            "opencv_default_ms": 1e3 * t_opencv / n,
            "keylo_ms": 1e3 * t_keylo / n,
            "speedup": t_opencv / t_keylo.max(f64::MIN_POSITIVE),
            "identical_images": identical,
        })
    );
    Ok(())
}
