//! `keylo sim`'s arguments.

use std::path::PathBuf;

use clap::{Args, Subcommand, ValueEnum};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SimFormat {
    /// keylo frame folder: organised grid with every channel (a valid `[source]`).
    Frames,
    /// KITTI-style velodyne .bin (x y z intensity float32), for other tools.
    KittiBin,
}

#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SimArgs {
    #[command(subcommand)]
    pub command: Option<SimCommand>,
    /// Scene: lab, corridor, road or park.
    #[arg(long, default_value = "lab")]
    pub scene: String,
    /// Number of frames.
    #[arg(long, default_value_t = 100)]
    pub frames: usize,
    /// Output directory.
    #[arg(long, required = true)]
    pub out: Option<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = SimFormat::Frames)]
    pub format: SimFormat,
    /// Any other simulator parameter, e.g. --set sensor=os1-64 --set seed=3 (see `keylo config show`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

#[derive(Debug, Subcommand)]
pub enum SimCommand {
    /// Compare simulated images with real ones: per detector the keypoint count and the
    /// keypoint study's metrics, and intensity and gradient histogram distances, per channel.
    Realism(crate::realism::RealismArgs),
}
