//! Detect + describe per image for any registered detector, on 8-bit grey PNGs resized
//! linearly to 1024×64 (`image_0000.png`…), REPEATS passes (default 1): milliseconds per
//! image (after one warm-up image) and keypoints per image, as JSON. OpenCV runs on one
//! thread; an ONNX model on its `threads` setting. Used for XFeat's FP32/INT8 timings
//! (docs/results/xfeat.md) and by `scripts/bench/surf_vs_opencv.sh` (build with the
//! feature `nonfree` for `surf`).
//!
//! Usage: detector_timing IMAGE_DIR COUNT KIND [PARAMS_TOML [REPEATS]]

#[path = "common/images.rs"]
mod images;

use std::path::Path;
use std::time::Instant;

use keylo_core::{Detector, Registry};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    keylo_features::keep_native_heap();
    opencv::core::set_num_threads(1)?;
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: detector_timing IMAGE_DIR COUNT KIND [PARAMS_TOML [REPEATS]]";
    let (dir, count, kind) = match args.as_slice() {
        [_, d, c, k, ..] => (Path::new(d), c.parse::<usize>()?, k.as_str()),
        _ => return Err(usage.into()),
    };
    let params: toml::Table = args.get(4).map_or(Ok(toml::Table::new()), |p| p.parse())?;
    let repeats: usize = args.get(5).map_or(Ok(1), |r| r.parse())?;
    if repeats == 0 {
        return Err("REPEATS: expected at least 1".into());
    }
    let images = images::load(dir, count, (1024, 64))?;
    let first = images.first().ok_or("COUNT: expected at least 1")?;
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let f = registry
        .detectors
        .get(kind)
        .ok_or("no such detector kind")?;
    let mut det: Box<dyn Detector> =
        f.build(&f.resolve(&params).map_err(|e| e.1)?, &Default::default())?;
    det.detect_and_describe(first)?;
    let mut keypoints = 0;
    let t = Instant::now();
    for _ in 0..repeats {
        for img in &images {
            keypoints += det.detect_and_describe(img)?.0.len();
        }
    }
    let n = (images.len() * repeats) as f64;
    println!(
        "{}",
        serde_json::json!({
            "kind": kind,
            "params": args.get(4).cloned().unwrap_or_default(),
            "images": images.len(),
            "ms_per_image": 1e3 * t.elapsed().as_secs_f64() / n,
            "keypoints_per_image": keypoints as f64 / n,
        })
    );
    Ok(())
}
