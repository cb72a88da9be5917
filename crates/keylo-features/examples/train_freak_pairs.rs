//! Trains FREAK's 512 descriptor pairs (the paper's greedy selection, see
//! `keylo_features::native::pairs_training`) on LiDAR images and writes the generated table.
//!
//! Usage: train_freak_pairs OUT.rs PCAP...
//! Every frame of every PCAP gives one 1024×64 image per channel it has (signal, range,
//! reflectivity, near-ir; all-black images skipped); FAST (threshold 20) and Shi-Tomasi
//! (the paper's block size 4, min distance 4) keypoints of each are described by FREAK's
//! oriented, scaled pattern with all 903 comparisons; 512 are selected.

use keylo_core::{BuildContext, Detector, Image, ImageBuilder, ImageSource, Registry};
use keylo_features::image::{LidarImageBuilder, LidarImageConfig};
use keylo_features::native::freak_pattern::{all_pairs, DESCRIPTOR_PAIRS};
use keylo_features::native::pairs_training::{render_table, select, BitColumns};
use keylo_features::native::{Freak, FreakParams, Integral};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};

const CHANNELS: [&str; 4] = ["signal", "range", "reflectivity", "near-ir"];
const DETECTORS: [(&str, &str); 2] = [
    ("fast", "threshold = 20"),
    (
        "shi-tomasi",
        "block_size = 4\nmin_distance = 4.0\nmax_corners = 16384",
    ),
];

type Error = Box<dyn std::error::Error>;

fn images_of(pcap: &str) -> Result<Vec<Image>, Error> {
    let config = OusterSourceConfig {
        path: pcap.to_string(),
        ..OusterSourceConfig::default()
    };
    let mut source = OusterSource::open(&config, &BuildContext::default())?;
    let mut out = Vec::new();
    while let Some(frame) = source.next_frame() {
        let frame = frame?;
        for ch in CHANNELS {
            let cfg = LidarImageConfig {
                images: vec![ch.to_string()],
                ..LidarImageConfig::default()
            };
            // A channel the recording's profile lacks is skipped, as are black images.
            let Ok(imgs) = LidarImageBuilder::new(cfg)?.build(&frame) else {
                continue;
            };
            out.extend(imgs.into_iter().filter(|i| i.data.iter().any(|p| *p != 0)));
        }
    }
    Ok(out)
}

fn main() -> Result<(), Error> {
    keylo_features::keep_native_heap();
    let args: Vec<String> = std::env::args().collect();
    let [_, out, pcaps @ ..] = args.as_slice() else {
        return Err("usage: train_freak_pairs OUT.rs PCAP...".into());
    };
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let ctx = BuildContext::default();
    let mut detectors: Vec<Box<dyn Detector>> = Vec::new();
    for (kind, params) in DETECTORS {
        let f = registry.detectors.get(kind).ok_or("detector")?;
        detectors.push(f.build(&f.resolve(&params.parse()?).map_err(|e| e.1)?, &ctx)?);
    }
    let freak = Freak::new(&FreakParams::default())?;
    let pairs = all_pairs();
    let mut bits = BitColumns::new(pairs.len());
    let mut images = 0;
    for pcap in pcaps {
        for img in images_of(pcap)? {
            images += 1;
            let sat = Integral::new(&img);
            for det in detectors.iter_mut() {
                for mut kp in det.detect(&img)? {
                    if let Some(v) = freak.field_values(&sat, &mut kp) {
                        bits.push_row(|c| v[pairs[c].0 as usize] > v[pairs[c].1 as usize]);
                    }
                }
            }
        }
    }
    let chosen = select(&bits, DESCRIPTOR_PAIRS)?;
    let table: Vec<(u8, u8)> = chosen.iter().map(|&c| pairs[c]).collect();
    let names: Vec<String> = pcaps
        .iter()
        .map(|p| {
            let name = std::path::Path::new(p).file_name().unwrap_or_default();
            format!("$OUSTER/{}", name.to_string_lossy())
        })
        .collect();
    let command = format!(
        "OUSTER=/work/shared/data/ouster && cargo run -p keylo-features --example train_freak_pairs -- \\\n//!   {out} \\\n//!   {}",
        names.join(" \\\n//!   ")
    );
    std::fs::write(out, render_table(&table, bits.rows(), &command))?;
    eprintln!(
        "{} keypoints from {images} images; {} pairs written to {out}",
        bits.rows(),
        table.len()
    );
    Ok(())
}
