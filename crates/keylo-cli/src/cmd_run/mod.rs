//! `keylo run`: build the pipeline from a config, run every frame, write and print results.

mod accuracy;
mod args;
mod finish;
mod out_dir;
mod process;

use std::process::ExitCode;
use std::sync::atomic::AtomicU64;
use std::sync::Arc;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use keylo::config::PipelineConfig;
use keylo::map::covariance::NoiseModel;
use keylo::map::{MapBuilder, PoseGraph};
use keylo::{ImageSource, Paced, Pipeline, Prefetched};

pub use args::RunArgs;
use out_dir::output_dir;
use process::{process_all, Outputs, RunState};

use crate::degeneracy_out;
use crate::journal::Journal;
use crate::overlay::Pictures;
use crate::report::{self, Summary};
use crate::{configs, resources, trajectories, view_out};

pub fn run(args: RunArgs, quiet: bool) -> Result<ExitCode> {
    let mut registry = keylo::registry();
    let config = configs::load(
        &mut registry,
        args.config.as_deref(),
        args.data.as_deref(),
        args.meta.as_deref(),
        &args.sets,
        args.trust.trust(),
    )?;
    // A ground-truth file named by the user must be readable before any work starts.
    let gt_given = accuracy::reference_file(&args, &config)?;
    // `[map]` (the map's settings, and the pose graph's keyframes) is checked before any work.
    let map_settings = match args.map_out.is_some() || config.output.pose_graph {
        true => Some(keylo::map::MapConfig::from_table(
            &config.map,
            &config.origin,
        )?),
        false => None,
    };
    let mut pose_graph = map_settings
        .as_ref()
        .and_then(|s| pose_graph_for(&config, s));
    let out = output_dir(&args, &config)?;
    let resolved = keylo::config::render_resolved(&config, &registry);
    std::fs::write(out.join("config.toml"), &resolved)
        .with_context(|| format!("writing {}", out.join("config.toml").display()))?;
    let Pipeline { source, odometry } = Pipeline::build(&config, &registry)?;
    let (source, late) = wrap_source(source, &args)?;
    let mut pipeline = Pipeline { source, odometry };
    let info = pipeline.source.info();
    tracing::info!("source: {}; output: {}", info.description, out.display());

    let reference = gt_given
        .as_ref()
        .map(|gt| {
            let mut t = gt.trajectory.clone();
            args.reference.stamp_map().apply(&mut t);
            t
        })
        .or_else(|| pipeline.source.ground_truth());
    let source = info.description.clone();
    let run = view_out::RunDescription::of(&config, resolved, source, Some(&pipeline.odometry));
    let run = view_out::RunDescription { reference, ..run };
    let mut view = view_out::start(&args.view, run, quiet)?;
    let progress = progress_bar(info.frames, quiet);
    let clock = resources::RunClock::start();
    let mut outcome = RunState::default();
    let mut journal = Journal::create(&out, &config.output)?;
    let mut pictures = args
        .images
        .map(|every| Pictures::new(every, out.join("images")));
    let mut map = match (&args.map_out, map_settings) {
        (Some(dir), Some(settings)) => Some(MapBuilder::create(dir, settings, &info.description)?),
        _ => None,
    };
    process_all(
        &mut pipeline,
        &config,
        &progress,
        &mut Outputs {
            journal: &mut journal,
            pictures: pictures.as_mut(),
            map: map.as_mut(),
            pose_graph: pose_graph.as_mut(),
            view: view.as_mut(),
        },
        &mut outcome,
    );
    progress.finish_and_clear();
    // The map holds the frames done, also when the run stopped early.
    let map = map.map(MapBuilder::finish).transpose()?;
    if let Some(g) = &pose_graph {
        finish::write_pose_graph(g, &out)?;
    }
    let (wall_hz, cpu_percent) = clock.rates(outcome.totals.frames);
    // After the rates: closing lets the viewers' queues drain (a fixed pause, not the frames'
    // time). A recording that cannot be closed fails the run, after its results are written.
    let view_error = view.map(|v| v.finish(&pipeline.odometry)).transpose().err();

    let mut summary = Summary {
        keylo_version: env!("CARGO_PKG_VERSION"),
        config: config.origin.clone(),
        source: info.description,
        frames_skipped: outcome.skipped,
        failed: outcome.failure,
        wall_hz,
        peak_rss_mb: resources::peak_rss_mb(),
        cpu_percent,
        path_length_m: outcome.trajectory.path_length(),
        playback_speed: args.realtime,
        frames_late: late.map(|n| n.load(std::sync::atomic::Ordering::Relaxed)),
        map: map.as_ref().zip(args.map_out.as_ref()).map(|(m, dir)| {
            serde_json::json!({
                "dir": dir.display().to_string(),
                "points": m.points,
                "keyframes": m.keyframes,
            })
        }),
        ..Summary::default()
    };
    outcome.totals.fill(&mut summary);
    summary.source_counters = pipeline.source.counters().into_iter().collect();
    report::log_counters(&summary.source_counters);
    summary.degeneracy = degeneracy_out::summarise(&outcome.degeneracy);
    summary.set_degenerate(&outcome.degenerate);
    let first = outcome.first_frame.unwrap_or_default();
    summary.all_degenerate = outcome.degenerate.all_of(summary.frames, first);
    // The options map the clock of a reference file given to the run, not a source's own.
    let map = match &gt_given {
        Some(_) => args.reference.stamp_map(),
        None => keylo::eval::stamp_map::StampMap::default(),
    };
    let gt = gt_given.or_else(|| {
        let t = pipeline.source.ground_truth()?;
        Some(trajectories::Labelled::stamped(
            t,
            "the source's ground truth",
        ))
    });
    accuracy::add_accuracy(&mut summary, &outcome.trajectory, gt, &out, map);
    // The map is for pictures: failing to write it must not lose the run's figures.
    if let Err(e) = write_map(&out, &pipeline.odometry) {
        tracing::warn!("no map.ply: {e:#}");
    }
    // summary.json comes last: `keylo compare` takes it as the mark of a finished run.
    degeneracy_out::write(&out, &outcome.degeneracy)?;
    report::write_summary(&out, &summary)?;

    if !quiet {
        println!("keylo run — {} → {}", summary.source, out.display());
        print!("{}", report::table(&summary));
    }
    Ok(finish::exit_status(
        &summary,
        (outcome.interrupted, &outcome.degenerate),
        view_error.as_ref(),
        &out,
    ))
}

/// How many frames `--realtime` released late (its [`Paced`] source counts them).
type LateFrames = Arc<AtomicU64>;

/// The source as the options ask for it: read ahead on a thread (`--prefetch`), released at
/// the sensor's rate (`--realtime`, with its count of frames that came late).
fn wrap_source(
    source: Box<dyn ImageSource>,
    args: &RunArgs,
) -> Result<(Box<dyn ImageSource>, Option<LateFrames>)> {
    let source: Box<dyn ImageSource> = match args.prefetch {
        0 => source,
        n => Box::new(Prefetched::new(source, usize::from(n))?),
    };
    Ok(match args.realtime {
        Some(speed) => {
            let paced = Paced::new(source, speed).context("--realtime")?;
            let late = paced.late_frames();
            (Box::new(paced), Some(late))
        }
        None => (source, None),
    })
}

/// The pose graph `[output] pose_graph` asks for: keyframes as the map's (`settings`),
/// covariances with `[output] covariance_sigma_m` or the registrar's fitted model.
fn pose_graph_for(config: &PipelineConfig, settings: &keylo::map::MapConfig) -> Option<PoseGraph> {
    config.output.pose_graph.then(|| {
        let sigma = config.output.covariance_sigma_m;
        let noise =
            NoiseModel::for_registrar(&config.registrar.kind, sigma, "output.covariance_sigma_m");
        PoseGraph::new(
            settings.keyframe_distance,
            settings.keyframe_angle_deg,
            noise,
        )
    })
}

/// The registrar's final local map as `map.ply` (world frame), when it has one.
fn write_map(out: &std::path::Path, odometry: &keylo::Odometry) -> Result<()> {
    let map = odometry.local_map();
    if map.is_empty() {
        return Ok(());
    }
    crate::cloud_ply::write(
        &out.join("map.ply"),
        &map,
        "keylo run: the registrar's local map after the last frame, world frame",
    )
}

fn progress_bar(len: Option<usize>, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(
        len.map(|n| n as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let style = ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {per_sec}  eta {eta}")
        .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar
}
