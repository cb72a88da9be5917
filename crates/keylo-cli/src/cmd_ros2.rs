//! `keylo ros2`: the pipeline of a config as a ROS 2 node (crate keylo-ros2), until Ctrl-C,
//! SIGTERM or `--idle-timeout`; with `--out`, the files `keylo run` writes.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Result;
use clap::Args;
use keylo::config::OnDegenerate;
use keylo::{Odometry, Trajectory};
use keylo_ros2::{Ros2Config, Ros2Node};

use crate::degenerate_out::DegenerateLog;
use crate::report::{self, Summary, Totals};
use crate::ros2_files::NodeFiles;
use crate::ros2_map::NodeMap;
use crate::{configs, resources, view_out};

#[derive(Debug, Args)]
pub struct Ros2Args {
    /// Pipeline config (TOML) with an optional [ros2] table (docs/ros2.md); none: raw
    /// KISS-ICP with the node's defaults.
    pub config: Option<PathBuf>,
    /// Override a config value, e.g. --set ros2.points_topic=/ouster/points (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    #[command(flatten)]
    pub trust: crate::arg_groups::TrustArgs,
    /// Also write what `keylo run` writes (trajectory, frames.csv, summary.json) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Save a global map of the node's frames in DIR (as `keylo run --map-out`; after a
    /// reset the next map goes to DIR-1, DIR-2, …); settings in `[map]` (docs/maps.md).
    #[arg(long, value_name = "DIR")]
    pub map_out: Option<PathBuf>,
    /// End when no cloud came for this many seconds (0: run until Ctrl-C or SIGTERM).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0)]
    pub idle_timeout: f64,
    #[command(flatten)]
    pub view: crate::arg_groups::ViewArgs,
}

pub fn run(args: Ros2Args, quiet: bool) -> Result<ExitCode> {
    let mut registry = keylo::registry();
    // No config: the built-in defaults (raw cloud, KISS-ICP), not the simulated demo.
    let config = configs::load_or_defaults(
        &mut registry,
        args.config.as_deref(),
        &args.sets,
        args.trust.trust(),
    )?;
    let ros2 = Ros2Config::from_table(&config.ros2, &config.origin)?;
    let mut map = match &args.map_out {
        Some(dir) => {
            let settings = keylo::map::MapConfig::from_table(&config.map, &config.origin)?;
            Some(NodeMap::start(dir, settings)?)
        }
        None => None,
    };
    let mut odometry = Odometry::build(&config, &registry)?;
    let resolved = keylo::config::render_resolved(&config, &registry);
    let mut files = NodeFiles::create(args.out.as_deref(), &resolved, &config.output)?;
    // A live sensor named by the config's [source] feeds the node instead of the points topic.
    let source = match config.source.kind.as_str() {
        "ouster-udp" => Some(keylo::build_source(&config, &registry)?),
        _ => None,
    };
    let mut node = Ros2Node::start(ros2, &odometry)?;
    node.set_registrar(&config.registrar.kind);
    let described = format!("keylo ros2 ({})", config.source.kind);
    let run = view_out::RunDescription::of(&config, resolved, described, Some(&odometry));
    let mut view = view_out::start(&args.view, run, quiet)?;
    node.want_features(map.as_ref().is_some_and(NodeMap::wants_features) || view.is_some());
    crate::interrupt::install("Ctrl-C will not end the node cleanly");
    let idle = (args.idle_timeout > 0.0).then(|| Duration::from_secs_f64(args.idle_timeout));
    let clock = resources::RunClock::start();
    let mut totals = Totals::default();
    let mut trajectory = Trajectory::default();
    let mut degenerate = DegenerateLog::default();
    let on_frame = |p: &keylo_ros2::Published| {
        totals.add(p.result);
        if let Some(why) = p.result.degenerate {
            let name = format!("frame {}", p.result.index);
            degenerate.record(p.result.index, &name, why, p.result.cloud_points);
            if config.output.on_degenerate == OnDegenerate::Error && degenerate.count == 1 {
                tracing::error!(
                    "{name}: output.on_degenerate = \"error\" does not stop a node; it goes on (said once; every degenerate frame is warned about as above)"
                );
            }
        }
        totals.odometry_seconds += p.seconds;
        if let Some(m) = map.as_mut() {
            m.add(p);
        }
        if let Some(v) = view.as_mut() {
            v.frame(p.odometry, p.frame, p.result, p.features, p.seconds);
        }
        trajectory.push(p.result.stamp, p.result.pose);
        files.record(p);
    };
    let (stats, counters) = match source {
        Some(source) => {
            let (stats, source) =
                node.run_source(&mut odometry, source, &crate::interrupt::STOP, on_frame);
            (stats, source.counters())
        }
        None => (
            node.run(&mut odometry, &crate::interrupt::STOP, idle, on_frame),
            Vec::new(),
        ),
    };
    let counters: std::collections::BTreeMap<String, u64> = counters.into_iter().collect();
    // A recording that cannot be closed is said after the node's own files are written.
    let view_error = view.map(|v| v.finish(&odometry)).transpose().err();
    let maps = map.map(NodeMap::finish).unwrap_or_default();
    report::log_counters(&counters);
    let (wall_hz, cpu_percent) = clock.rates(totals.frames);
    if !quiet {
        eprintln!(
            "keylo ros2: {} clouds received, {} registered, {} dropped (registration behind), \
             {} refused, {} undecodable",
            stats.clouds_received,
            stats.frames,
            stats.clouds_dropped,
            stats.clouds_refused,
            stats.messages_undecodable
        );
    }
    if let Some(dir) = &args.out {
        let mut summary = Summary {
            keylo_version: env!("CARGO_PKG_VERSION"),
            config: config.origin.clone(),
            source: if counters.is_empty() {
                "ROS 2 topic (keylo ros2)".into()
            } else {
                format!("{} (keylo ros2)", config.source.kind)
            },
            wall_hz,
            peak_rss_mb: resources::peak_rss_mb(),
            cpu_percent,
            path_length_m: trajectory.path_length(),
            ros2: serde_json::to_value(&stats).ok(),
            map: (!maps.is_empty()).then(|| {
                let list: Vec<serde_json::Value> = (maps.iter())
                    .map(|(dir, m)| {
                        serde_json::json!({
                            "dir": dir.display().to_string(),
                            "points": m.points,
                            "keyframes": m.keyframes,
                        })
                    })
                    .collect();
                serde_json::Value::Array(list)
            }),
            source_counters: counters,
            ..Summary::default()
        };
        totals.fill(&mut summary);
        summary.set_degenerate(&degenerate);
        report::write_summary(dir, &summary)?;
    }
    let write_error = files.finish();
    if let Some(e) = view_error {
        eprintln!("error: {e:#} (the node's own files are written)");
        return Ok(ExitCode::FAILURE);
    }
    if let Some(e) = write_error {
        return Err(e.context("the node ran, but its files are incomplete"));
    }
    Ok(ExitCode::SUCCESS)
}
