//! `keylo localise MAP --data X`: each frame of X registered against a saved map's fixed
//! cloud (docs/maps.md, "Localisation"); per frame its pose in the map, a fitness and whether
//! it is tracking.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use clap::Args;
use keylo::map::localise::{LocaliseConfig, Localiser};
use keylo::map::Map;
use keylo::{Pose, Trajectory};
use nalgebra::{Quaternion, Translation3, UnitQuaternion};

use crate::configs;

#[derive(Debug, Args)]
pub struct LocaliseArgs {
    /// The map folder (`keylo run … --map-out DIR`).
    pub map: PathBuf,
    /// The data to localise (any source `keylo run --data` reads).
    #[arg(long)]
    pub data: PathBuf,
    /// A config whose `[source]` reads the data and whose `[localise]` table sets the
    /// registration (docs/config.md); none: the defaults.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The sensor's pose in the map at the first frame's end, "x y z qx qy qz qw" (default: the
    /// map's first keyframe).
    #[arg(long, value_name = "POSE", allow_hyphen_values = true)]
    pub initial_pose: Option<String>,
    /// Override a config value, e.g. --set localise.voxel_size=0.3 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Output folder: trajectory.tum (the map's frame) and localise.csv.
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: LocaliseArgs, quiet: bool) -> Result<ExitCode> {
    let map = Map::open(&args.map)?;
    let mut registry = keylo::registry();
    let config = configs::load(
        &mut registry,
        args.config.as_deref(),
        Some(&args.data),
        None,
        &args.sets,
    )?;
    let settings = LocaliseConfig::from_table(&config.localise, &config.origin)?;
    let initial = match &args.initial_pose {
        Some(text) => parse_pose(text)?,
        None => match map.keyframes().first() {
            Some(k) => k.pose,
            None => bail!(
                "{}: the map has no keyframe; give --initial-pose",
                args.map.display()
            ),
        },
    };
    check_inside(&map, &initial)?;
    let mut localiser = Localiser::new(&map.points()?, initial, settings);
    let mut source = keylo::build_source(&config, &registry)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let csv_path = args.out.join("localise.csv");
    let mut csv = std::io::BufWriter::new(
        std::fs::File::create(&csv_path)
            .with_context(|| format!("creating {}", csv_path.display()))?,
    );
    writeln!(csv, "frame,stamp,fitness,tracking,iterations,points,ms")?;
    let mut trajectory = Trajectory::default();
    let (mut lost, mut seconds) = (0usize, 0.0);
    let mut first = true;
    while let Some(frame) = source.next_frame() {
        let frame = frame?;
        let t = std::time::Instant::now();
        let l = localiser.localise(&frame, first);
        let s = t.elapsed().as_secs_f64();
        seconds += s;
        first = false;
        let stamp = frame.end_stamp();
        if !l.tracking {
            lost += 1;
            tracing::warn!(
                "frame {}: not tracking (fitness {:.2})",
                frame.index,
                l.fitness
            );
        }
        trajectory.push(stamp, l.pose);
        writeln!(
            csv,
            "{},{stamp:.9},{:.4},{},{},{},{:.3}",
            frame.index,
            l.fitness,
            l.tracking,
            l.iterations,
            l.points,
            1e3 * s
        )?;
    }
    csv.flush()?;
    let tum = args.out.join("trajectory.tum");
    keylo::io::trajectory::write_tum(&tum, &trajectory)
        .with_context(|| format!("writing {}", tum.display()))?;
    let n = trajectory.len();
    if !quiet {
        println!(
            "keylo localise: {n} frames in {} ({} map points): {} tracking, {lost} lost; {:.1} Hz \
             registration → {}",
            args.map.display(),
            localiser.map_points(),
            n - lost,
            n as f64 / seconds.max(1e-9),
            args.out.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// "x y z qx qy qz qw" as a pose; the error says what is wrong.
fn parse_pose(text: &str) -> Result<Pose> {
    let v: Vec<f64> = text
        .split([' ', ','])
        .filter(|s| !s.is_empty())
        .map(str::parse)
        .collect::<Result<_, _>>()
        .with_context(|| {
            format!("--initial-pose \"{text}\": expected seven numbers x y z qx qy qz qw")
        })?;
    let [x, y, z, qx, qy, qz, qw] = v[..] else {
        bail!(
            "--initial-pose \"{text}\": {} numbers; expected seven (x y z qx qy qz qw)",
            v.len()
        );
    };
    if v.iter().any(|c| !c.is_finite()) {
        bail!("--initial-pose \"{text}\": not every number is finite");
    }
    let q = Quaternion::new(qw, qx, qy, qz);
    if (q.norm() - 1.0).abs() > 1e-3 {
        bail!(
            "--initial-pose \"{text}\": the quaternion's norm is {}; expected 1 (a rotation)",
            q.norm()
        );
    }
    Ok(Pose::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_quaternion(q),
    ))
}

/// How far outside the map's box (x, y, z) an initial position may lie, m.
const OUTSIDE_MARGIN_M: f64 = 5.0;

/// An initial pose farther than [`OUTSIDE_MARGIN_M`] outside the map's box is an error naming
/// both (a pose in another frame, or meant for another map).
fn check_inside(map: &Map, pose: &Pose) -> Result<()> {
    let Some(b) = &map.manifest().bounds else {
        bail!(
            "{}: the map holds no point to localise in",
            map.dir().display()
        );
    };
    let p = pose.translation.vector;
    let outside =
        (0..3).any(|k| p[k] < b.min[k] - OUTSIDE_MARGIN_M || p[k] > b.max[k] + OUTSIDE_MARGIN_M);
    if outside {
        bail!(
            "--initial-pose ({:.2}, {:.2}, {:.2}) lies outside the map {} (box {:.2?} .. {:.2?}, \
             {OUTSIDE_MARGIN_M} m margin): expected a pose in the map's world frame",
            p.x,
            p.y,
            p.z,
            map.dir().display(),
            b.min,
            b.max
        );
    }
    Ok(())
}
