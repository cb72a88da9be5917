//! `keylo localise MAP --data X`: each frame of X registered against a saved map's fixed
//! cloud (docs/maps.md, "Localisation"); per frame its pose in the map, a fitness and whether
//! it is tracking.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, Context, Result};
use clap::Args;
use keylo::map::localise::{initial_pose, pose_of_text, pose_of_values, LocaliseConfig, Localiser};
use keylo::map::Map;
use keylo::{FrameResult, MapFit, Trajectory};

use crate::report::Failure;
use crate::{configs, view_out};

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
    #[command(flatten)]
    pub trust: crate::arg_groups::TrustArgs,
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
    #[command(flatten)]
    pub view: crate::arg_groups::ViewArgs,
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
        args.trust.trust(),
    )?;
    let settings = LocaliseConfig::from_table(&config.localise, &config.origin)?;
    if !settings.map.is_empty() && std::path::Path::new(&settings.map) != args.map {
        tracing::warn!(
            "{}: localise.map = \"{}\" is not used: the map is the command line's {}",
            config.origin,
            settings.map,
            args.map.display()
        );
    }
    let given = match (&args.initial_pose, settings.initial_pose.as_slice()) {
        (Some(text), _) => Some(pose_of_text(text).map_err(|e| anyhow!("--initial-pose {e}"))?),
        (None, []) => None,
        (None, v) => Some(pose_of_values(v).map_err(|e| anyhow!("localise.initial_pose: {e}"))?),
    };
    let initial = initial_pose(&map, given)?;
    let prior = map.points()?;
    let mut localiser = Localiser::new(&prior, initial, settings)?;
    let mut source = keylo::build_source(&config, &registry)?;
    let resolved = keylo::config::render_resolved(&config, &registry);
    let run = view_out::RunDescription::of(&config, resolved, source.info().description, None);
    let run = view_out::RunDescription {
        reference: source.ground_truth(),
        world_frame: "map",
        fixed_map: true,
        ..run
    };
    let mut view = view_out::start(&args.view, run, quiet)?;
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
    // Ctrl-C or SIGTERM: stop after the current frame, write what is done, close the
    // recording.
    crate::interrupt::install("Ctrl-C will not save partial results");
    // A frame the source cannot read stops the run; the frames before it are kept, as in
    // `keylo run`.
    let mut failure: Option<Failure> = None;
    let mut next = 0u64;
    while let Some(frame) = source.next_frame() {
        if crate::interrupt::requested() {
            break;
        }
        let frame = match frame {
            Ok(f) => f,
            Err(e) => {
                failure = Some(Failure {
                    frame: next,
                    error: e.to_string(),
                });
                break;
            }
        };
        next = frame.index + 1;
        let t = std::time::Instant::now();
        let l = localiser.localise(&frame);
        let s = t.elapsed().as_secs_f64();
        seconds += s;
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
        if let Some(v) = view.as_mut() {
            let mut result = FrameResult::with_pose(frame.index, stamp, l.pose);
            result.iterations = l.iterations;
            result.converged = l.converged;
            result.registered_points = l.points;
            result.map_points = prior.len();
            result.fit = Some(MapFit {
                fitness: l.fitness,
                tracking: l.tracking,
            });
            // The prior map is fixed: sent with the first frame, then every N frames for
            // viewers that connect later.
            let map = v.wants_map().then_some(prior.as_slice());
            v.send(&frame, &result, None, None, map, s);
        }
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
    let view_error = view.map(|v| v.finish_with(&prior)).transpose().err();
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
    // A recording that could not be closed is said first and exits 1, unless the run itself
    // has a more telling status (a frame that could not be read, an interruption).
    if let Some(e) = &view_error {
        eprintln!("error: {e:#} (trajectory.tum and localise.csv are written)");
    }
    if let Some(f) = failure {
        f.say(n, &args.out);
        return Ok(ExitCode::from(crate::EXIT_FRAME_FAILED));
    }
    if crate::interrupt::requested() {
        eprintln!(
            "interrupted: the {n} frames done are written to {}",
            args.out.display()
        );
        return Ok(ExitCode::from(crate::EXIT_INTERRUPTED));
    }
    if view_error.is_some() {
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}
