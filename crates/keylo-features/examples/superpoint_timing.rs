//! Times SuperPoint on real 1024×64 LiDAR images, for `scripts/bench/superpoint_timing.sh`.
//!
//! Usage: superpoint_timing IMAGE_DIR REPEATS THREADS PCAP...
//! Builds the two-plane signal+range image and the one-plane signal and range images of every
//! frame (the paper configs' settings: 1024×64 linear, range gamma 0.5), writes them to
//! IMAGE_DIR as raw 8-bit files (the Python side reads the same bytes), then prints one JSON
//! object: milliseconds per image for the network plus decoding, per image kind.

use std::collections::BTreeMap;
use std::time::Instant;

use keylo_core::{BuildContext, Detector, Image, ImageBuilder, ImageSource};
use keylo_features::image::{LidarImageBuilder, LidarImageConfig, Normalise};
use keylo_features::superpoint::{ExecutionProvider, SuperPoint, SuperPointParams};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};

fn images(pcaps: &[String]) -> Result<Vec<Image>, Box<dyn std::error::Error>> {
    let mut config = LidarImageConfig {
        images: vec!["signal+range".into(), "signal".into(), "range".into()],
        ..LidarImageConfig::default()
    };
    let gamma = Normalise {
        gamma: 0.5,
        ..Normalise::default()
    };
    config.normalise_by_channel.insert("range".into(), gamma);
    let mut builder = LidarImageBuilder::new(config)?;
    let mut out = Vec::new();
    for pcap in pcaps {
        let config = OusterSourceConfig {
            path: pcap.clone(),
            ..OusterSourceConfig::default()
        };
        let mut source = OusterSource::open(&config, &BuildContext::default())?;
        while let Some(frame) = source.next_frame() {
            out.extend(builder.build(&frame?)?);
        }
    }
    Ok(out)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, dir, repeats, threads, pcaps @ ..] = args.as_slice() else {
        return Err("usage: superpoint_timing IMAGE_DIR REPEATS THREADS PCAP...".into());
    };
    let (repeats, threads): (usize, usize) = (repeats.parse()?, threads.parse()?);
    let images = images(pcaps)?;
    let params = SuperPointParams {
        threads,
        execution_provider: ExecutionProvider::Cpu,
        ..SuperPointParams::default()
    };
    let mut sp = SuperPoint::new(params, &BuildContext::default())?;
    let mut ms: BTreeMap<String, (f64, usize, usize)> = BTreeMap::new();
    for (i, image) in images.iter().enumerate() {
        let name = image.name();
        std::fs::write(
            format!(
                "{dir}/{i:03}_{name}_{}x{}x{}.u8",
                image.width, image.height, image.channels
            ),
            &image.data,
        )?;
        let k = sp.detect(image)?; // warm-up, and the keypoint count
        let start = Instant::now();
        for _ in 0..repeats {
            std::hint::black_box(sp.detect_and_describe(image)?);
        }
        let e = ms.entry(name).or_default();
        e.0 += start.elapsed().as_secs_f64() * 1e3 / repeats as f64;
        e.1 += 1;
        e.2 += k.len();
    }
    let per: Vec<String> = ms
        .iter()
        .map(|(n, (t, c, k))| {
            format!(
                "\"{n}\": {{\"ms\": {:.3}, \"keypoints\": {:.1}}}",
                t / *c as f64,
                *k as f64 / *c as f64
            )
        })
        .collect();
    println!(
        "{{\"threads\": {threads}, \"repeats\": {repeats}, \"images\": {}, \"per_image\": {{{}}}}}",
        images.len(),
        per.join(", ")
    );
    Ok(())
}
