//! `keylo compare`'s arguments.

use std::path::PathBuf;

use clap::{Args, Subcommand};

use crate::arg_groups::MergeArgs;

#[derive(Debug, Args)]
#[command(
    after_help = "Grid keys are any --set key; k_sig and k_rng (or downsampler.k_sig, \
downsampler.k_rng) stand for downsampler.windows.signal and downsampler.windows.range, and \
window sizes are merged into one downsampler.windows table per run. Example (the paper's \
neighbour-size table): keylo compare configs/paper/outdoor-akaze-kiss-icp.toml --data SEQ \
--grid k_sig=4,5,7 --grid k_rng=4,5,7. Across machines: --shard I/N per machine, then \
`keylo compare merge OUT SHARD_DIR...` (docs/scale-out.md).",
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
pub struct CompareArgs {
    #[command(subcommand)]
    pub command: Option<CompareCommand>,
    /// Pipeline configs (TOML) to compare; none: the built-in default pipeline.
    pub configs: Vec<PathBuf>,
    /// Data to run every config on (repeatable: each is one column of the tables).
    #[arg(long, required = true)]
    pub data: Vec<PathBuf>,
    /// Ground truth (TUM or KITTI) for a single --data; default: gt.tum beside each data.
    #[arg(long)]
    pub gt: Option<PathBuf>,
    #[command(flatten)]
    pub reference: crate::reference_args::ReferenceArgs,
    /// Output folder: compare.md/.csv/.json, plots/, runs/<data>/<variant>/.
    #[arg(long, default_value = "compare")]
    pub out: PathBuf,
    /// Runs at a time (each is its own process; more than one perturbs CPU % and rate).
    #[arg(long, default_value_t = 1)]
    pub jobs: usize,
    /// A grid axis KEY=V1,V2,… (repeatable; every combination is run).
    #[arg(long = "grid", value_name = "KEY=V1,V2,...")]
    pub grids: Vec<String>,
    /// Override a config value in every run (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    #[command(flatten)]
    pub trust: crate::arg_groups::TrustArgs,
    /// Diverged when the largest aligned translation error exceeds this (m).
    #[arg(long, default_value_t = 2.0)]
    pub diverge_ape: f64,
    /// Diverged when one step between consecutive estimated poses exceeds this (m).
    #[arg(long, default_value_t = 5.0)]
    pub diverge_step: f64,
    /// Largest stamp difference (s) when pairing poses with ground truth (evo `--t_max_diff`).
    #[arg(long, default_value_t = 0.01)]
    pub t_max_diff: f64,
    /// Stop a run that takes longer than this (seconds): SIGTERM, then SIGKILL after a 10 s
    /// grace. Its frames so far are kept and its row says it timed out.
    #[arg(long, value_name = "SECONDS")]
    pub timeout: Option<f64>,
    /// Run again even where a finished summary.json is found.
    #[arg(long)]
    pub rerun: bool,
    /// Play every run's data back at the sensor's rate (`keylo run --realtime`): frames
    /// released at their timestamps (SPEED × real time; no value: 1), so the CPU (%) and
    /// peak RSS columns are those at that rate, as the paper measures them. Use with
    /// `--jobs 1` (the default) or the runs perturb each other's figures.
    #[arg(long, value_name = "SPEED", num_args = 0..=1, default_missing_value = "1")]
    pub realtime: Option<f64>,
    /// Pictures of frames 0, N, 2N, … of every run (`keylo run --images`), which
    /// `keylo report` of the compare folder shows; they do not change any figure.
    #[arg(long, value_name = "EVERY_N", value_parser = clap::value_parser!(u64).range(1..))]
    pub images: Option<u64>,
    /// Print the planned runs (folder and --set overrides) and stop.
    #[arg(long)]
    pub dry_run: bool,
    /// Same-budget baselines: every keypoint config (downsampler `keypoint-neighbourhood`)
    /// also runs with its keypoint windows replaced by a `random` and by a `voxel-budget`
    /// sample of as many points per frame as the windows select.
    #[arg(long)]
    pub same_budget: bool,
    /// No plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Do only shard I of N (0-based) of the runs: a deterministic part, balanced by expected
    /// cost, into `--out` with a manifest (shard.json); join the shards' folders with
    /// `keylo compare merge`. Re-running a shard skips its finished runs.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<crate::shard::Shard>,
}

#[derive(Debug, Subcommand)]
pub enum CompareCommand {
    /// Join the folders of every shard of one `keylo compare --shard I/N` study into the
    /// tables and plots one process would have written.
    Merge(MergeArgs),
}
