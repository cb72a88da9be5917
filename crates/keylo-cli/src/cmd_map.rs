//! `keylo map info|export|crop`: the chores on a saved map folder (docs/maps.md).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use keylo::map::{Bounds, Map};

#[derive(Debug, Subcommand)]
pub enum MapCommand {
    /// What a map folder holds: its version, settings, points, bounds and keyframes.
    Info {
        /// The map folder (`keylo run … --map-out DIR`).
        map: PathBuf,
        /// Print map.json's contents as JSON instead of a summary.
        #[arg(long)]
        json: bool,
    },
    /// Write the map's cloud (world frame; x, y, z, intensity) as one PLY or PCD file,
    /// optionally only the points inside a box.
    Export {
        /// The map folder.
        map: PathBuf,
        /// The file to write: `.ply` or `.pcd`.
        out: PathBuf,
        #[command(flatten)]
        within: Corners,
    },
    /// A new map folder with the points and keyframes inside a box (--min and --max).
    Crop {
        /// The map folder.
        map: PathBuf,
        #[command(flatten)]
        within: Corners,
        /// The new map's folder.
        #[arg(long)]
        out: PathBuf,
    },
}

/// A box in the world frame, by two corners.
#[derive(Debug, Args)]
pub struct Corners {
    /// The box's lower corner, "X,Y,Z" (metres, world frame; with --max).
    #[arg(
        long,
        value_name = "X,Y,Z",
        requires = "max",
        allow_hyphen_values = true
    )]
    min: Option<String>,
    /// The box's upper corner, "X,Y,Z" (with --min).
    #[arg(
        long,
        value_name = "X,Y,Z",
        requires = "min",
        allow_hyphen_values = true
    )]
    max: Option<String>,
}

impl Corners {
    /// The box, when both corners are given; the error names a corner that does not parse.
    fn bounds(&self) -> Result<Option<Bounds>> {
        match (&self.min, &self.max) {
            (Some(min), Some(max)) => bounds(min, max).map(Some),
            _ => Ok(None),
        }
    }
}

pub fn run(cmd: MapCommand) -> Result<ExitCode> {
    match cmd {
        MapCommand::Info { map, json } => info(&map, json),
        MapCommand::Export { map, out, within } => {
            let n = Map::open(&map)?.export(&out, within.bounds()?.as_ref())?;
            println!("wrote {n} points to {}", out.display());
            Ok(ExitCode::SUCCESS)
        }
        MapCommand::Crop { map, within, out } => {
            let Some(within) = within.bounds()? else {
                bail!("keylo map crop needs the box: --min X,Y,Z --max X,Y,Z");
            };
            let m = Map::open(&map)?.crop(&within, &out)?;
            println!(
                "wrote {} ({} points, {} keyframes)",
                out.display(),
                m.points,
                m.keyframes
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn info(dir: &Path, json: bool) -> Result<ExitCode> {
    let map = Map::open(dir)?;
    let m = map.manifest();
    if json {
        println!("{}", serde_json::to_string_pretty(m)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "keylo map {} (format {} version {}, keylo {})",
        dir.display(),
        m.format,
        m.version,
        m.keylo_version
    );
    println!("  source       {}", m.source);
    println!("  frame        {}", m.frame);
    println!("  frames       {}", m.frames);
    println!(
        "  points       {} (voxel {} m)",
        m.points, m.settings.voxel_size
    );
    if let Some(b) = &m.bounds {
        let f = |v: [f64; 3]| format!("{:.2}, {:.2}, {:.2}", v[0], v[1], v[2]);
        println!("  bounds       min {}  max {}", f(b.min), f(b.max));
    }
    let with = if m.keyframe_features {
        ", with keypoints and descriptors"
    } else {
        ""
    };
    println!(
        "  keyframes    {}{with} (every {} m or {}°)",
        m.keyframes, m.settings.keyframe_distance, m.settings.keyframe_angle_deg
    );
    if let (Some(first), Some(last)) = (map.keyframes().first(), map.keyframes().last()) {
        println!("  time         {:.3} .. {:.3} s", first.stamp, last.stamp);
    }
    if let Some(from) = &m.cropped_from {
        println!("  cropped from {from}");
    }
    Ok(ExitCode::SUCCESS)
}

/// The box between two "X,Y,Z" corners; the error names the option.
fn bounds(min: &str, max: &str) -> Result<Bounds> {
    let parse = |text: &str, option: &str| -> Result<[f64; 3]> {
        let v: Vec<f64> = text
            .split([',', ' '])
            .filter(|s| !s.is_empty())
            .map(str::parse)
            .collect::<Result<_, _>>()
            .with_context(|| format!("--{option} \"{text}\": expected three numbers X,Y,Z"))?;
        match v[..] {
            [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([x, y, z]),
            _ => bail!("--{option} \"{text}\": expected three finite numbers X,Y,Z"),
        }
    };
    let b = Bounds {
        min: parse(min, "min")?,
        max: parse(max, "max")?,
    };
    if (0..3).any(|k| b.min[k] > b.max[k]) {
        bail!("--min {min} lies above --max {max} on some axis; expected min ≤ max");
    }
    Ok(b)
}
