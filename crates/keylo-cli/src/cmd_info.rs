//! `keylo info PATH`: what a data path holds (kind, frames, duration, sensor, resolution,
//! format details), and with `--image N --out DIR` frame N's channel images as PNG.

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use keylo::io::export::png_image::write_channel_png;
use keylo::{Channel, GridOccupancy, LidarFrame};
use serde::Serialize;

use std::path::PathBuf;

use clap::Args;

use crate::arg_groups::DataArgs;
use crate::{configs, EXIT_FRAME_FAILED};

/// What `keylo info` reports.
#[derive(Debug, Default, Serialize)]
struct Info {
    kind: String,
    path: String,
    description: String,
    details: Vec<(String, String)>,
    frames: usize,
    duration_s: Option<f64>,
    rows: usize,
    cols: usize,
    sensor: String,
    mean_valid_pixels: f64,
    /// Unorganised sources: how their points fill the image grid (`None` for organised ones).
    points: Option<PointStats>,
    channels_with_data: Vec<String>,
    ground_truth_poses: Option<usize>,
    images_written: Vec<String>,
    error: Option<String>,
}

/// How the points of an unorganised source fill its grid, per frame on average.
#[derive(Debug, Default, Serialize)]
struct PointStats {
    /// Finite points per frame (every one reaches `passthrough`).
    mean_points: f64,
    /// Points per frame outside the grid (beyond the vertical field of view, at the origin).
    mean_outside: f64,
    /// Points per frame sharing a pixel with a nearer one (the images show one of them).
    mean_sharing: f64,
    /// Share of the points that share a pixel, percent.
    sharing_pct: f64,
    /// Most points in one pixel over all frames.
    max_per_pixel: usize,
}

impl PointStats {
    fn add(&mut self, o: &GridOccupancy) {
        self.mean_points += o.points as f64;
        self.mean_outside += o.outside as f64;
        self.mean_sharing += o.sharing as f64;
        self.max_per_pixel = self.max_per_pixel.max(o.max_per_pixel);
    }

    fn finish(&mut self, frames: usize) {
        let n = frames.max(1) as f64;
        self.mean_points /= n;
        self.mean_outside /= n;
        self.mean_sharing /= n;
        self.sharing_pct = 100.0 * self.mean_sharing / self.mean_points.max(1.0);
    }
}

pub fn run(args: InfoArgs) -> Result<ExitCode> {
    let mut registry = keylo::registry();
    let (kind, mut source) = configs::open_data(&mut registry, &args.data)?;
    let mut info = Info {
        kind,
        path: args.data.data.display().to_string(),
        description: source.info().description,
        ..Info::default()
    };
    let mut pictures = match &args.config {
        Some(config) => Some(crate::overlay::Single::build(
            config,
            &args.data,
            args.trust.trust(),
        )?),
        None => None,
    };
    let (mut first, mut last, mut valid) = (None, None, 0usize);
    let mut has_data = [false; 4];
    while let Some(frame) = source.next_frame() {
        let frame = match frame {
            Ok(f) => f,
            Err(e) => {
                info.error = Some(format!("frame {}: {e}", info.frames));
                break;
            }
        };
        if args.image == Some(info.frames) {
            if let Some(out) = &args.out {
                info.images_written = match pictures.as_mut() {
                    Some(p) => p.write(out, &frame)?,
                    None => write_images(out, &frame)?,
                };
            }
        }
        first.get_or_insert(frame.timestamp);
        last = Some(frame.timestamp);
        (info.rows, info.cols) = (frame.rows, frame.cols);
        info.sensor.clone_from(&frame.beams.model);
        valid += frame.valid_count();
        if let Some(scan) = &frame.scan {
            info.points
                .get_or_insert_with(PointStats::default)
                .add(&scan.occupancy());
        }
        for (k, c) in Channel::ALL.into_iter().enumerate() {
            has_data[k] |= frame.channel(c).iter().any(|v| *v != 0.0);
        }
        info.frames += 1;
    }
    info.details = source.details();
    info.duration_s = first.zip(last).map(|(a, b)| b - a);
    info.mean_valid_pixels = valid as f64 / info.frames.max(1) as f64;
    if let Some(p) = info.points.as_mut() {
        p.finish(info.frames);
    }
    info.channels_with_data = Channel::ALL
        .into_iter()
        .zip(has_data)
        .filter(|(_, has)| *has)
        .map(|(c, _)| c.name().to_string())
        .collect();
    info.ground_truth_poses = source.ground_truth().map(|t| t.len());
    if let (Some(n), true) = (args.image, info.images_written.is_empty()) {
        info.error.get_or_insert(format!(
            "--image {n}: the data holds {} frames (0..{})",
            info.frames, info.frames
        ));
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        print_text(&info);
    }
    Ok(match &info.error {
        Some(e) => {
            eprintln!("error: {e}");
            ExitCode::from(EXIT_FRAME_FAILED)
        }
        None => ExitCode::SUCCESS,
    })
}

fn write_images(out: &Path, frame: &LidarFrame) -> Result<Vec<String>> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut written = Vec::new();
    for c in Channel::ALL {
        let path = out.join(format!("frame{:06}_{}.png", frame.index, c.name()));
        write_channel_png(&path, frame, c)?;
        written.push(path.display().to_string());
    }
    Ok(written)
}

fn print_text(info: &Info) {
    let row = |k: &str, v: String| println!("  {k:<22} {v}");
    println!("{}", info.path);
    row("kind", info.kind.clone());
    row("source", info.description.clone());
    for (k, v) in &info.details {
        row(k, v.clone());
    }
    row("frames", info.frames.to_string());
    if let Some(d) = info.duration_s {
        row("duration (s)", format!("{d:.3}"));
    }
    if !info.details.iter().any(|(k, _)| k == "sensor") {
        row("sensor", info.sensor.clone());
    }
    row(
        "resolution",
        format!("{} x {} (rows x cols)", info.rows, info.cols),
    );
    row(
        "valid pixels (mean)",
        format!("{:.0}", info.mean_valid_pixels),
    );
    if let Some(p) = &info.points {
        row("points (mean)", format!("{:.0}", p.mean_points));
        row(
            "sharing a pixel (mean)",
            format!(
                "{:.0} ({:.1} %; at most {} in one pixel)",
                p.mean_sharing, p.sharing_pct, p.max_per_pixel
            ),
        );
        row("outside the grid (mean)", format!("{:.0}", p.mean_outside));
    }
    row("channels with data", info.channels_with_data.join(", "));
    if let Some(n) = info.ground_truth_poses {
        row("ground truth", format!("{n} poses"));
    }
    for p in &info.images_written {
        row("wrote", p.clone());
    }
}

#[derive(Debug, Args)]
pub struct InfoArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// Write the channel images of frame N (0-based) as PNG into --out.
    #[arg(long, value_name = "N", requires = "out")]
    pub image: Option<usize>,
    /// Folder for the PNG images of --image.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// With --image: run this pipeline config's stages on frame N and draw, as `keylo run
    /// --images` does, each detector image with its keypoints and the pixels whose points
    /// are registered, and a top view of the raw and registered points.
    #[arg(long, requires = "image")]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub trust: crate::arg_groups::TrustArgs,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}
