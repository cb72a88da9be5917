//! keylo's `brief` and `freak` (defaults: OpenCV contrib's patterns) on the keypoints OpenCV
//! described, against OpenCV's own descriptors (row hashes from
//! `scripts/bench/brief_freak_opencv_dump.py`): the share of keypoints kept alike and of rows
//! identical, per descriptor and keypoint set, as JSON. `scripts/bench/brief_freak_vs_opencv.sh`
//! runs both.
//!
//! Usage: brief_freak_vs_opencv IMAGE_DIR DUMP.json

#[path = "common/images.rs"]
mod images;

use std::path::Path;

use keylo_core::{Channel, DescriptorData, Image, Keypoint, Registry};
use keylo_features::image::{resize_plane, Interpolation};
use sha2::{Digest, Sha256};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, dir, dump] = args.as_slice() else {
        return Err("usage: brief_freak_vs_opencv IMAGE_DIR DUMP.json".into());
    };
    let dump: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dump)?)?;
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let mut totals = serde_json::Map::new();
    let images = dump["images"].as_array().ok_or("no images")?;
    for (i, entry) in images.iter().enumerate() {
        let (data, rows, cols) =
            images::read_png(&Path::new(dir).join(format!("image_{i:04}.png")))?;
        let mut img = Image::new_gray(1024, 64, Channel::Signal);
        img.data = resize_plane(&data, rows, cols, 1024, 64, Interpolation::Linear)?;
        for (set, sets) in entry.as_object().ok_or("entry")? {
            let given: Vec<Keypoint> = (sets["keypoints"].as_array().ok_or("keypoints")?.iter())
                .enumerate()
                .map(|(j, k)| {
                    let f = |n: usize| k[n].as_f64().unwrap_or(f64::NAN) as f32;
                    Keypoint {
                        x: f(0),
                        y: f(1),
                        size: f(2),
                        angle: f(3),
                        response: f(4),
                        octave: k[5].as_i64().unwrap_or(0) as i32,
                        class_id: j as i32,
                    }
                })
                .collect();
            for kind in ["brief", "freak"] {
                let f = registry.descriptors.get(kind).ok_or("descriptor")?;
                let mut d = f.build(
                    &f.resolve(&toml::Table::new()).map_err(|e| e.1)?,
                    &Default::default(),
                )?;
                let mut kps = given.clone();
                let desc = d.describe(&img, &mut kps)?;
                let DescriptorData::Binary(bytes) = &desc.data else {
                    return Err("binary descriptors expected".into());
                };
                let ours: Vec<(i32, String)> = kps
                    .iter()
                    .zip(bytes.chunks(desc.dim.max(1)))
                    .map(|(k, r)| {
                        let h: String = Sha256::digest(r)[..8]
                            .iter()
                            .map(|b| format!("{b:02x}"))
                            .collect();
                        (k.class_id, h)
                    })
                    .collect();
                let want = &sets[kind];
                let kept: Vec<i64> = (want["kept"].as_array().ok_or("kept")?.iter())
                    .filter_map(|v| v.as_i64())
                    .collect();
                let rows: Vec<&str> = (want["rows"].as_array().ok_or("rows")?.iter())
                    .filter_map(|v| v.as_str())
                    .collect();
                let theirs: std::collections::HashMap<i64, &str> =
                    kept.iter().copied().zip(rows.iter().copied()).collect();
                let same = ours
                    .iter()
                    .filter(|(c, h)| theirs.get(&i64::from(*c)) == Some(&h.as_str()))
                    .count();
                let key = format!("{set}_{kind}");
                let t = totals
                    .entry(key)
                    .or_insert_with(|| serde_json::json!([0, 0, 0]));
                let add = |t: &mut serde_json::Value, k: usize, v: usize| {
                    t[k] = (t[k].as_u64().unwrap_or(0) + v as u64).into();
                };
                add(t, 0, kept.len());
                add(t, 1, ours.len());
                add(t, 2, same);
            }
        }
    }
    let report: serde_json::Map<String, serde_json::Value> = totals
        .into_iter()
        .map(|(k, v)| {
            let (opencv, keylo, same) = (v[0].as_u64(), v[1].as_u64(), v[2].as_u64());
            let (o, kl, s) = (opencv.unwrap_or(0), keylo.unwrap_or(0), same.unwrap_or(0));
            let share = if o == 0 { 1.0 } else { s as f64 / o as f64 };
            (k, serde_json::json!({"opencv_rows": o, "keylo_rows": kl, "identical": s, "share": share}))
        })
        .collect();
    println!("{}", serde_json::Value::Object(report));
    Ok(())
}
