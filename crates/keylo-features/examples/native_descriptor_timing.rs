//! Milliseconds per describe call of keylo's native `brief` and `freak` on the parity fixture,
//! timed as `tests/fixtures/native_descriptors/make_golden.py` times OpenCV's (all 28
//! image × keypoint-set calls, 10 times; the fastest of 5 rounds), so the two compare on a
//! shared machine. Prints one JSON object.
//!
//! Usage: cargo run --release -p keylo-features --example native_descriptor_timing

use std::io::BufReader;
use std::path::PathBuf;
use std::time::Instant;

use keylo_core::{BuildContext, Channel, Descriptor, Image, Keypoint, Registry};

const REPEATS: usize = 10;
const ROUNDS: usize = 5;

type Error = Box<dyn std::error::Error>;

fn fixture() -> Result<Vec<(Image, Vec<Keypoint>)>, Error> {
    let dir =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/native_descriptors");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("keypoints.json"))?)?;
    let mut out = Vec::new();
    for v in doc["images"].as_object().ok_or("images")?.values() {
        let file = std::fs::File::open(dir.join(v["file"].as_str().ok_or("file")?))?;
        let mut reader = png::Decoder::new(BufReader::new(file)).read_info()?;
        let mut buf = vec![0; reader.output_buffer_size().ok_or("png size")?];
        let info = reader.next_frame(&mut buf)?;
        let mut img = Image::new_gray(info.width as usize, info.height as usize, Channel::Signal);
        img.data = buf[..img.data.len()].to_vec();
        for rows in v["keypoints"].as_object().ok_or("sets")?.values() {
            let f = |r: &serde_json::Value, i: usize| r[i].as_f64().unwrap_or(f64::NAN) as f32;
            let kps = rows
                .as_array()
                .ok_or("rows")?
                .iter()
                .map(|r| Keypoint {
                    x: f(r, 0),
                    y: f(r, 1),
                    size: f(r, 2),
                    angle: f(r, 3),
                    ..Keypoint::default()
                })
                .collect();
            out.push((img.clone(), kps));
        }
    }
    Ok(out)
}

fn main() -> Result<(), Error> {
    let cases = fixture()?;
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let mut result = serde_json::Map::new();
    for kind in ["brief", "freak"] {
        let f = registry.descriptors.get(kind).ok_or("kind")?;
        let params = f.resolve(&toml::Table::new()).map_err(|e| e.1)?;
        let mut d: Box<dyn Descriptor> = f.build(&params, &BuildContext::default())?;
        let mut best = f64::INFINITY;
        for _ in 0..ROUNDS {
            let t = Instant::now();
            for _ in 0..REPEATS {
                for (img, kps) in &cases {
                    let mut kps = kps.clone();
                    d.describe(img, &mut kps)?;
                }
            }
            best = best.min(t.elapsed().as_secs_f64());
        }
        let ms = best * 1e3 / (REPEATS * cases.len()) as f64;
        result.insert(kind.into(), ms.into());
    }
    println!("{}", serde_json::Value::Object(result));
    Ok(())
}
