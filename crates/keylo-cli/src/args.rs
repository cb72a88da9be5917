//! The command line: the global options and the subcommands (each owns its arguments).

use clap::{Parser, Subcommand};

/// keylo: keypoint-assisted LiDAR odometry.
#[derive(Debug, Parser)]
#[command(name = "keylo", version, about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// More log output (-v info, -vv debug, -vvv trace); KEYLO_LOG overrides.
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    pub verbose: u8,
    /// Only errors; no progress bar.
    #[arg(short, long, global = true)]
    pub quiet: bool,
    /// Worker threads (default: one per core).
    #[arg(long, global = true)]
    pub threads: Option<usize>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run odometry: with no CONFIG and no --data, the built-in simulated demo.
    Run(crate::cmd_run::RunArgs),
    /// Simulate an Ouster-like sensor in a scene and write frames + ground truth.
    Sim(crate::cmd_sim::SimArgs),
    /// ATE/RPE of an estimated trajectory against a reference (TUM or KITTI files).
    Eval(crate::cmd_eval::EvalArgs),
    /// Show what a data path holds; with --image N, write frame N's channel images as PNG
    /// (with --config, its keypoints, registered pixels and a top view).
    Info(crate::cmd_info::InfoArgs),
    /// Write the frames of any source as KITTI .bin, PLY, PCD or a keylo frame folder.
    Convert(crate::cmd_convert::ConvertArgs),
    /// Run several configs (and a grid of overrides) on the same data; tables and plots.
    Compare(crate::compare::CompareArgs),
    /// One self-contained report.html of a run or compare folder: tables, plots, pictures
    /// and 3-D views of the map, trajectories and points (opens offline).
    Report(crate::report_page::ReportArgs),
    /// Inspect configs and the registered backends.
    #[command(subcommand)]
    Config(crate::cmd_config::ConfigCommand),
    /// Evaluate keypoint detectors and descriptors on LiDAR images (the paper's six metrics),
    /// and sweep image size × interpolation.
    #[command(subcommand)]
    Keypoints(crate::keypoints::KeypointsCommand),
    /// Localise the frames of some data in a saved map: each frame registered against the
    /// map's fixed cloud, with a fitness and a tracking flag (docs/maps.md).
    Localise(crate::cmd_localise::LocaliseArgs),
    /// The chores on a saved map folder (`keylo run … --map-out DIR`): info, export, crop.
    #[command(subcommand)]
    Map(crate::cmd_map::MapCommand),
    /// List and check run-time plugins (`kind = "plugin:NAME"`); see docs/plugins.md.
    #[command(subcommand)]
    Plugins(crate::cmd_plugins::PluginsCommand),
    /// Run the pipeline as a ROS 2 node: PointCloud2 in; Odometry, TF and Path out
    /// (pure Rust over DDS, no ROS install; docs/ros2.md).
    #[cfg(feature = "ros2")]
    Ros2(crate::cmd_ros2::Ros2Args),
}
