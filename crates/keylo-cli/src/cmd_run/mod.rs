//! `keylo run`: build the pipeline from a config, run every frame, write and print results.

mod accuracy;
mod args;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use keylo::config::{OnBadFrame, OnDegenerate, PipelineConfig};
use keylo::map::covariance::NoiseModel;
use keylo::map::{MapBuilder, PoseGraph};
use keylo::{CoreError, ImageSource, Paced, Pipeline, Prefetched, Trajectory};

pub use args::RunArgs;

use crate::degeneracy_out::{self, DegeneracyRow};
use crate::degenerate_out::{self, DegenerateLog};
use crate::journal::Journal;
use crate::overlay::Pictures;
use crate::report::{self, Failure, Summary, Totals};
use crate::{
    configs, resources, trajectories, view_out, EXIT_DEGENERATE, EXIT_FRAME_FAILED,
    EXIT_INTERRUPTED,
};

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
    let source: Box<dyn ImageSource> = match args.prefetch {
        0 => source,
        n => Box::new(Prefetched::new(source, usize::from(n))?),
    };
    let (source, late): (Box<dyn ImageSource>, _) = match args.realtime {
        Some(speed) => {
            let paced = Paced::new(source, speed).context("--realtime")?;
            let late = paced.late_frames();
            (Box::new(paced), Some(late))
        }
        None => (source, None),
    };
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
        g.write(&out.join("pose_graph.g2o"))?;
        if g.fallbacks > 0 {
            tracing::warn!(
                "pose_graph.g2o: {} frame(s) had no covariance estimate; their edges use the \
                 fallback variance {}",
                g.fallbacks,
                keylo::map::FALLBACK_VARIANCE
            );
        }
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
    // A recording that could not be closed is said first and exits 1, unless the run itself
    // has a more telling status.
    if let Some(e) = &view_error {
        eprintln!(
            "error: {e:#}\n       the run's results are written to {}",
            out.display()
        );
    }
    if let Some(f) = &summary.failed {
        eprintln!(
            "error: stopped at frame {}: {}\n       the {} frames done before it are written to {}",
            f.frame,
            f.error,
            summary.frames,
            out.display()
        );
        let code = if outcome.interrupted {
            EXIT_INTERRUPTED
        } else {
            EXIT_FRAME_FAILED
        };
        return Ok(ExitCode::from(code));
    }
    if let Some(line) = outcome.degenerate.closing(summary.frames) {
        tracing::warn!("{line}");
    }
    if summary.all_degenerate {
        eprintln!(
            "error: no frame of the {} was registered with all six pose directions constrained \
             (every frame after the first degenerate): the trajectory is the motion model's \
             prediction, not odometry (written to {} all the same)",
            summary.frames,
            out.display()
        );
        return Ok(ExitCode::from(EXIT_DEGENERATE));
    }
    if view_error.is_some() {
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}

#[derive(Default)]
struct RunState {
    trajectory: Trajectory,
    totals: Totals,
    skipped: usize,
    failure: Option<Failure>,
    interrupted: bool,
    degeneracy: Vec<DegeneracyRow>,
    degenerate: DegenerateLog,
    /// Index of the first frame registered.
    first_frame: Option<u64>,
}

/// Where each frame's results go besides the trajectory.
struct Outputs<'a> {
    journal: &'a mut Journal,
    pictures: Option<&'a mut Pictures>,
    map: Option<&'a mut MapBuilder>,
    pose_graph: Option<&'a mut PoseGraph>,
    view: Option<&'a mut view_out::Session>,
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

fn process_all(
    pipeline: &mut Pipeline,
    config: &PipelineConfig,
    progress: &ProgressBar,
    outputs: &mut Outputs,
    st: &mut RunState,
) {
    // Ctrl-C or SIGTERM: the run stops after the current frame and writes what it has.
    crate::interrupt::install("Ctrl-C will not save partial results");
    // Index of the next frame, for messages about a frame the source could not read.
    let mut next = 0u64;
    loop {
        if crate::interrupt::requested() {
            st.failure = Some(Failure {
                frame: next,
                error: "interrupted (Ctrl-C or SIGTERM)".into(),
            });
            st.interrupted = true;
            break;
        }
        let frame = match pipeline.source.next_frame() {
            None => break,
            Some(Ok(f)) => f,
            Some(Err(e)) => {
                st.failure = Some(Failure {
                    frame: next,
                    error: e.to_string(),
                });
                break;
            }
        };
        next = frame.index + 1;
        let pictured = outputs
            .pictures
            .as_ref()
            .is_some_and(|p| p.wants(frame.index));
        let mapped = (outputs.map.as_ref()).is_some_and(|m| m.config().keyframe_features);
        let viewed = outputs.view.is_some();
        let t = Instant::now();
        let result = pipeline
            .odometry
            .process_guarded(&frame, pictured || mapped || viewed);
        let seconds = t.elapsed().as_secs_f64();
        st.totals.odometry_seconds += seconds;
        progress.inc(1);
        match result {
            Ok((r, features)) => {
                if let Some(why) = r.degenerate {
                    let name = frame_name(pipeline, frame.index);
                    st.degenerate
                        .record(frame.index, &name, why, r.cloud_points);
                    if config.output.on_degenerate == OnDegenerate::Error {
                        st.failure = Some(Failure {
                            frame: frame.index,
                            error: degenerate_out::stop_message(&why),
                        });
                        break;
                    }
                }
                st.first_frame.get_or_insert(frame.index);
                st.trajectory.push(r.stamp, r.pose);
                st.totals.add(&r);
                if let Some(fit) = r.fit.filter(|f| !f.tracking) {
                    tracing::warn!(
                        "{}: not tracking in the map (fitness {:.2}); its pose is not to be \
                         trusted",
                        frame_name(pipeline, frame.index),
                        fit.fitness
                    );
                }
                let row = report::FrameRow {
                    frame: frame.index,
                    stamp: r.stamp,
                    keypoints: r.keypoints,
                    cloud_points: r.cloud_points,
                    registered_points: r.registered_points,
                    map_points: r.map_points,
                    odometry_ms: 1e3 * seconds,
                    rss_mb: resources::rss_mb(),
                    degenerate: r.degenerate.map(|d| d.label()),
                };
                if let Some(d) = r.degeneracy.clone() {
                    tracing::debug!(
                        "frame {}: condition {:.3e}, {} weak direction(s), weakest {:?}",
                        frame.index,
                        d.condition,
                        d.weak,
                        d.eigenvectors[0]
                    );
                    st.degeneracy.push(DegeneracyRow {
                        frame: frame.index,
                        degeneracy: d,
                    });
                }
                let recorded = outputs
                    .journal
                    .record(r.stamp, &r.pose, &row)
                    .and_then(|()| match (outputs.pictures.as_deref_mut(), &features) {
                        (Some(p), Some(f)) if pictured => p.record(&pipeline.odometry, &frame, f),
                        _ => Ok(()),
                    })
                    .map(|()| {
                        if let Some(g) = outputs.pose_graph.as_deref_mut() {
                            g.add(&r);
                        }
                    })
                    .and_then(|()| match outputs.map.as_deref_mut() {
                        Some(m) => m
                            .add(&frame, &r, features.as_ref())
                            .map(|_| ())
                            .map_err(Into::into),
                        None => Ok(()),
                    });
                if let Some(v) = outputs.view.as_deref_mut() {
                    v.frame(&pipeline.odometry, &frame, &r, features.as_ref(), seconds);
                }
                if let Err(e) = recorded {
                    st.failure = Some(Failure {
                        frame: frame.index,
                        error: crate::error_chain(&e),
                    });
                    break;
                }
            }
            Err(e @ CoreError::BadFrame { .. })
                if config.output.on_bad_frame == OnBadFrame::Skip =>
            {
                tracing::warn!("skipping {}: {e}", frame_name(pipeline, frame.index));
                st.skipped += 1;
            }
            Err(e) => {
                let error = match pipeline.source.frame_origin(frame.index) {
                    Some(file) => format!("{e} (file {file})"),
                    None => e.to_string(),
                };
                st.failure = Some(Failure {
                    frame: frame.index,
                    error,
                });
                break;
            }
        }
    }
}

/// "frame N" and, when the source reads one file per frame, "(FILE)".
fn frame_name(pipeline: &Pipeline, index: u64) -> String {
    match pipeline.source.frame_origin(index) {
        Some(file) => format!("frame {index} ({file})"),
        None => format!("frame {index}"),
    }
}

fn output_dir(args: &RunArgs, config: &PipelineConfig) -> Result<PathBuf> {
    let dir = match (&args.out, config.output.dir_path()) {
        (Some(d), _) => d.clone(),
        (None, Some(d)) => config.base_dir.join(d),
        (None, None) => {
            let secs = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs());
            PathBuf::from("runs").join(timestamp_name(secs))
        }
    };
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("creating output directory {}", dir.display()))?;
    Ok(dir)
}

/// `YYYYMMDD-HHMMSS` (UTC) of a Unix time.
fn timestamp_name(secs: u64) -> String {
    let days = secs / 86_400;
    let rem = secs % 86_400;
    // civil-from-days (Howard Hinnant's algorithm)
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}-{:02}{:02}{:02}",
        rem / 3600,
        (rem / 60) % 60,
        rem % 60
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

#[cfg(test)]
mod tests {
    #[test]
    fn timestamps_are_civil_dates() {
        assert_eq!(super::timestamp_name(0), "19700101-000000");
        assert_eq!(super::timestamp_name(1_795_000_000), "20261118-110640");
    }
}
