//! SURF detect + describe per image (keylo's `surf`, feature `nonfree`), one thread, on
//! 8-bit grey PNGs resized linearly to 1024×64; prints milliseconds per image and keypoints
//! per image as JSON. `scripts/bench/surf_vs_opencv.sh` runs it beside OpenCV 3.4.2's SURF
//! from Python on the same images.
//!
//! Usage: surf_timing IMAGE_DIR [COUNT] [REPEATS]

#[path = "common/images.rs"]
mod images;

use std::path::Path;
use std::time::Instant;

use keylo_core::{Detector, Registry};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    keylo_features::keep_native_heap();
    opencv::core::set_num_threads(1)?;
    let args: Vec<String> = std::env::args().collect();
    let dir = Path::new(
        args.get(1)
            .ok_or("usage: surf_timing IMAGE_DIR [COUNT] [REPEATS]")?,
    );
    let count: usize = args.get(2).map_or(Ok(200), |s| s.parse())?;
    let repeats: usize = args.get(3).map_or(Ok(3), |s| s.parse())?;
    let images = images::load(dir, count, (1024, 64))?;
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let f = registry.detectors.get("surf").ok_or("no surf detector")?;
    let mut surf: Box<dyn Detector> = f.build(
        &f.resolve(&"describe = true".parse()?).map_err(|e| e.1)?,
        &Default::default(),
    )?;
    let mut keypoints = 0;
    let t = Instant::now();
    for _ in 0..repeats.max(1) {
        for img in &images {
            keypoints += surf.detect_and_describe(img)?.0.len();
        }
    }
    let n = (images.len() * repeats.max(1)).max(1) as f64;
    println!(
        "{}",
        serde_json::json!({
            "tool": "keylo",
            "images": images.len(),
            "ms_per_image": 1e3 * t.elapsed().as_secs_f64() / n,
            "keypoints_per_image": keypoints as f64 / n,
        })
    );
    Ok(())
}
