//! Writes the golden-fixture inputs of the native BRIEF/FREAK parity test:
//! 1024×64 images (PNG) of consecutive real Ouster frames and of controlled transforms, the
//! keypoints both sides describe (`keypoints.json`), and the image pairs to evaluate.
//!
//! Usage: make_native_descriptor_fixtures OUT_DIR OUSTER_DIR
//! (OUSTER_DIR: the ouster-sdk sample recordings, `shared/data/ouster`). The command that was
//! run is in `tests/fixtures/native_descriptors/README.md`.

use std::io::BufWriter;
use std::path::Path;

use keylo_core::{BuildContext, Detector, Image, ImageBuilder, ImageSource, Keypoint, Registry};
use keylo_features::image::{LidarImageBuilder, LidarImageConfig};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};
use serde_json::{json, Value};

type Error = Box<dyn std::error::Error>;

/// (short name, recording, channels, frames used): every sample with consecutive complete
/// frames (keylo's Ouster source drops the partial first frame of the OS-0-128 capture; the
/// 2-frame `crc_test` gives one complete frame; the other samples have one frame each).
/// The low-data OS-1-128 profile has no signal channel: near-ir instead.
const SEQUENCES: [(&str, &str, &[&str], &[usize]); 2] = [
    (
        "os0-128",
        "OS-0-128_v3.0.1_1024x10_from_osf.pcap",
        &["signal", "range"],
        &[0, 1],
    ),
    (
        "os1-128",
        "OS-1-128_v2.3.0_1024x10_lb_n3.pcap",
        &["near-ir", "range"],
        &[0, 1, 2],
    ),
];

/// The keypoint sets: (name, detector kind, parameters; the paper's).
const DETECTORS: [(&str, &str, &str); 2] = [
    ("fast", "fast", "threshold = 30"),
    (
        "shi-tomasi",
        "shi-tomasi",
        "block_size = 4\nmin_distance = 4.0\nmax_corners = 16384",
    ),
];

fn frames(path: &Path) -> Result<Vec<keylo_core::LidarFrame>, Error> {
    let config = OusterSourceConfig {
        path: path.display().to_string(),
        ..OusterSourceConfig::default()
    };
    let mut source = OusterSource::open(&config, &BuildContext::default())?;
    let mut out = Vec::new();
    while let Some(f) = source.next_frame() {
        out.push(f?);
    }
    Ok(out)
}

fn write_png(path: &Path, img: &Image) -> Result<(), Error> {
    let file = std::fs::File::create(path)?;
    let mut enc = png::Encoder::new(BufWriter::new(file), img.width as u32, img.height as u32);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()?.write_image_data(&img.data)?;
    Ok(())
}

/// `img` warped by the affine `h` (row-major 3×3, last row 0 0 1; maps source pixels to
/// output pixels), bilinear, black outside.
fn warp(img: &Image, h: &[f64; 9]) -> Image {
    let det = h[0] * h[4] - h[1] * h[3];
    let inv = [h[4] / det, -h[1] / det, -h[3] / det, h[0] / det];
    let mut out = img.clone();
    let (w, hh) = (img.width as f64, img.height as f64);
    let px = |x: usize, y: usize| f64::from(img.data[y * img.stride + x]);
    for y in 0..img.height {
        for x in 0..img.width {
            let (dx, dy) = (x as f64 - h[2], y as f64 - h[5]);
            let (sx, sy) = (inv[0] * dx + inv[1] * dy, inv[2] * dx + inv[3] * dy);
            let v = if sx < 0.0 || sy < 0.0 || sx > w - 1.0 || sy > hh - 1.0 {
                0.0
            } else {
                let (x0, y0) = (sx.floor() as usize, sy.floor() as usize);
                let (x1, y1) = ((x0 + 1).min(img.width - 1), (y0 + 1).min(img.height - 1));
                let (fx, fy) = (sx - x0 as f64, sy - y0 as f64);
                let top = px(x0, y0) * (1.0 - fx) + px(x1, y0) * fx;
                let bottom = px(x0, y1) * (1.0 - fx) + px(x1, y1) * fx;
                top * (1.0 - fy) + bottom * fy
            };
            out.data[y * img.stride + x] = v.round().clamp(0.0, 255.0) as u8;
        }
    }
    out
}

fn shift(dx: f64, dy: f64) -> [f64; 9] {
    [1.0, 0.0, dx, 0.0, 1.0, dy, 0.0, 0.0, 1.0]
}

fn rotation(degrees: f64, cx: f64, cy: f64) -> [f64; 9] {
    let (s, c) = degrees.to_radians().sin_cos();
    [
        c,
        -s,
        cx - c * cx + s * cy,
        s,
        c,
        cy - s * cx - c * cy,
        0.0,
        0.0,
        1.0,
    ]
}

fn keypoint_rows(kps: &[Keypoint]) -> Value {
    kps.iter()
        .map(|k| json!([k.x, k.y, k.size, k.angle, k.response, k.octave, k.class_id]))
        .collect()
}

struct Writer {
    out: std::path::PathBuf,
    detectors: Vec<(&'static str, Box<dyn Detector>)>,
    images: serde_json::Map<String, Value>,
}

impl Writer {
    fn add(&mut self, name: &str, img: &Image) -> Result<(), Error> {
        let file = format!("images/{name}.png");
        write_png(&self.out.join(&file), img)?;
        let mut sets = serde_json::Map::new();
        for (set, det) in self.detectors.iter_mut() {
            sets.insert(set.to_string(), keypoint_rows(&det.detect(img)?));
        }
        self.images
            .insert(name.into(), json!({ "file": file, "keypoints": sets }));
        Ok(())
    }
}

fn main() -> Result<(), Error> {
    keylo_features::keep_native_heap();
    let args: Vec<String> = std::env::args().collect();
    let [_, out, ouster] = args.as_slice() else {
        return Err("usage: make_native_descriptor_fixtures OUT_DIR OUSTER_DIR".into());
    };
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let ctx = BuildContext::default();
    let mut detectors = Vec::new();
    for (set, kind, params) in DETECTORS {
        let f = registry.detectors.get(kind).ok_or("detector")?;
        detectors.push((
            set,
            f.build(&f.resolve(&params.parse()?).map_err(|e| e.1)?, &ctx)?,
        ));
    }
    let out = Path::new(out).to_path_buf();
    std::fs::create_dir_all(out.join("images"))?;
    let mut w = Writer {
        out,
        detectors,
        images: serde_json::Map::new(),
    };
    let mut pairs = Vec::new();
    let mut bases = Vec::new();
    for (seq, file, channels, used) in SEQUENCES {
        let frames = frames(&Path::new(ouster).join(file))?;
        for ch in channels {
            let mut builder = LidarImageBuilder::new(LidarImageConfig {
                images: vec![ch.to_string()],
                ..LidarImageConfig::default()
            })?;
            let mut prev: Option<String> = None;
            for &i in used {
                let frame = frames.get(i).ok_or("missing frame")?;
                let img = builder.build(frame)?.remove(0);
                let name = format!("{seq}_{ch}_f{i}");
                w.add(&name, &img)?;
                if let Some(p) = prev.replace(name.clone()) {
                    pairs.push(
                        json!({"name": format!("{p}->{name}"), "prev": p, "next": name,
                        "kind": "consecutive", "homography": null}),
                    );
                }
                if i == used[1] && *ch != "range" {
                    bases.push((name, img));
                }
            }
        }
    }
    for (base, img) in bases {
        let controlled = [
            ("shift-5-2", shift(5.0, 2.0)),
            ("rot-3deg", rotation(3.0, 511.5, 31.5)),
        ];
        for (tag, h) in controlled {
            let name = format!("{base}_{tag}");
            w.add(&name, &warp(&img, &h))?;
            pairs.push(
                json!({"name": format!("{base}->{tag}"), "prev": base, "next": name,
                "kind": tag, "homography": h}),
            );
        }
    }
    let doc = json!({
        "source": "ouster-sdk sample recordings (BSD-3-Clause), 1024x64 linear images",
        "keypoint_columns": ["x", "y", "size", "angle", "response", "octave", "class_id"],
        "detectors": DETECTORS.iter().map(|(s, k, p)| json!({"set": s, "kind": k, "params": p})).collect::<Vec<_>>(),
        "images": w.images,
        "pairs": pairs,
    });
    std::fs::write(w.out.join("keypoints.json"), serde_json::to_string(&doc)?)?;
    eprintln!(
        "{} images, {} pairs",
        doc["images"].as_object().map_or(0, |m| m.len()),
        pairs.len()
    );
    Ok(())
}
