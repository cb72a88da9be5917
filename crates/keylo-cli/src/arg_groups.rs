//! Argument groups shared by several subcommands (flattened into each).

use std::path::PathBuf;

use clap::Args;

/// The data a command reads: a path whose kind is detected, its metadata, overrides.
#[derive(Debug, Args)]
pub struct DataArgs {
    /// Data path (pcap, bag, mcap, KITTI/PLY/PCD folder, keylo frame folder, …).
    pub data: PathBuf,
    /// Sensor metadata (an Ouster capture's JSON when it is not X.json beside X.pcap).
    #[arg(long)]
    pub meta: Option<PathBuf>,
    /// Override a source parameter, e.g. --set source.max_frames=10 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

/// `… merge OUT DIR...` of a sharded study.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Output folder of the merged tables and plots.
    pub out: PathBuf,
    /// The shards' output folders (every shard of the study, once each).
    #[arg(required = true, num_args = 1..)]
    pub dirs: Vec<PathBuf>,
    /// No plots.
    #[arg(long)]
    pub no_plots: bool,
}
