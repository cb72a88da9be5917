use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

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
    Run(RunArgs),
    /// Simulate an Ouster-like sensor in a scene and write frames + ground truth.
    Sim(SimArgs),
    /// ATE/RPE of an estimated trajectory against a reference (TUM or KITTI files).
    Eval(EvalArgs),
    /// Inspect configs and the registered backends.
    #[command(subcommand)]
    Config(ConfigCommand),
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// Pipeline config (TOML); see docs/config.md.
    pub config: Option<PathBuf>,
    /// Data to read instead of `[source]` (kind auto-detected).
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Ground-truth trajectory (TUM or KITTI) for accuracy figures.
    #[arg(long)]
    pub gt: Option<PathBuf>,
    /// Output directory (default: `[output] dir`, else runs/<timestamp>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a config value, e.g. --set registrar.voxel_size=0.5 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SimFormat {
    /// keylo frame folder: organised grid with every channel (a valid `[source]`).
    Frames,
    /// KITTI-style velodyne .bin (x y z intensity float32), for other tools.
    KittiBin,
}

#[derive(Debug, Args)]
pub struct SimArgs {
    /// Scene: lab, corridor or road.
    #[arg(long, default_value = "lab")]
    pub scene: String,
    /// Number of frames.
    #[arg(long, default_value_t = 100)]
    pub frames: usize,
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = SimFormat::Frames)]
    pub format: SimFormat,
    /// Any other simulator parameter, e.g. --set sensor=os1-64 --set seed=3 (see `keylo config show`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Estimated trajectory (TUM or KITTI).
    #[arg(long)]
    pub est: PathBuf,
    /// Reference trajectory (TUM or KITTI).
    #[arg(long)]
    pub gt: PathBuf,
    /// Also print the result as JSON.
    #[arg(long)]
    pub json: bool,
    /// An extra RPE over this delta (as `evo_rpe --delta`), e.g. `--delta 10 --delta-unit m`.
    #[arg(long)]
    pub delta: Option<f64>,
    /// Unit of --delta.
    #[arg(long, value_enum, default_value_t = DeltaUnit::Frames)]
    pub delta_unit: DeltaUnit,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DeltaUnit {
    /// Pairs `delta` frames apart.
    Frames,
    /// Pairs `delta` metres of reference path apart.
    M,
}

#[derive(Debug, Subcommand)]
pub enum ConfigCommand {
    /// Print a config with every default filled in and every key documented.
    Show {
        /// Config file (default: the built-in demo config).
        file: Option<PathBuf>,
        /// Override a value (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
    },
    /// List the registered backends of every stage.
    Kinds,
    /// Print the Markdown config reference (docs/config.md is generated with this).
    Docs,
}
