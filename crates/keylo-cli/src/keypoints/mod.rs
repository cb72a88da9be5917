//! `keylo keypoints eval` and `keylo keypoints sweep`: the paper's keypoint study as commands
//! (metrics and the sweep are in `keylo-kpeval`; this module reads the input, shows progress,
//! and writes tables and plots).

pub(crate) mod eval;
mod eval_report;
pub(crate) mod input;
mod pictures;
mod plots;
mod reference;
mod report;
mod shards;
mod sweep;
mod sweep_report;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Result;
use clap::{Args, Subcommand};

#[derive(Debug, Subcommand)]
pub enum KeypointsCommand {
    /// The six metrics of every detector/descriptor combination over consecutive frames.
    Eval(EvalArgs),
    /// The paper's Algorithm 1: the metrics for every interpolation × width × height.
    Sweep(SweepArgs),
}

/// What both commands read and how.
#[derive(Debug, Args)]
pub struct InputArgs {
    /// Data: any path `keylo run --data` reads (pcap, bag, mcap, KITTI/PLY/PCD folder, keylo
    /// frame folder), or a folder of PNG images (8- or 16-bit, taken in natural name order).
    #[arg(long = "data", required = true)]
    pub data_path: Option<PathBuf>,
    /// Sensor metadata (an Ouster capture's JSON when it is not X.json beside X.pcap).
    #[arg(long)]
    pub meta: Option<PathBuf>,
    /// Combinations: `paper` (the paper's 32), `all` (every valid pair, plugins included), or
    /// a list such as AKAZE_AKAZE,ORB_ORB,FAST_BRIEF,SUPERPOINT.
    #[arg(long, default_value = "paper")]
    pub combos: String,
    /// A folder of plugin libraries (repeatable; then `KEYLO_PLUGIN_PATH` and
    /// ~/.local/lib/keylo/plugins): their detectors and descriptors become `plugin:NAME`
    /// combinations, e.g. `plugin:loam-edges_BRIEF`, and join `all`.
    #[arg(long = "plugin-dir", value_name = "DIR")]
    pub plugin_dirs: Vec<PathBuf>,
    #[command(flatten)]
    pub trust: crate::arg_groups::TrustArgs,
    /// Evaluation settings (TOML: `preset`, `[image]`, `[metrics]`, `[params.<kind>]`; see
    /// docs/keypoint-eval.md).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Frames to evaluate (after --start and --stride).
    #[arg(long, default_value_t = 100)]
    pub frames: usize,
    /// Frames skipped at the start.
    #[arg(long, default_value_t = 0)]
    pub start: usize,
    /// Take every N-th frame (the paper's 1146 images are every 10th).
    #[arg(long, default_value_t = 1)]
    pub stride: usize,
    /// Channel of LiDAR frames (overrides `[image] channel`).
    #[arg(long)]
    pub channel: Option<String>,
    /// Detector groups (eval) or sweep tasks run at a time (default: one per core). With more
    /// than one, OpenCV's own threads are turned off so times are single-thread times.
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Output folder.
    #[arg(long = "out", required = true)]
    pub out_dir: Option<PathBuf>,
    /// No plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Do only shard I of N (0-based) of the work: a deterministic part (eval: detector group
    /// × block of 25 images; sweep: cell × detector group), balanced by expected cost, into
    /// `--out` with a manifest (shard.json); join the shards with `… merge OUT DIR...`.
    /// Re-running a shard skips its finished items.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<crate::shard::Shard>,
}

impl InputArgs {
    /// `--data` (clap requires it unless `merge` is given).
    pub fn data(&self) -> &Path {
        self.data_path.as_deref().unwrap_or(Path::new(""))
    }

    /// `--out` (clap requires it unless `merge` is given).
    pub fn out(&self) -> &Path {
        self.out_dir.as_deref().unwrap_or(Path::new(""))
    }
}

/// `merge`: the shards of one study joined.
#[derive(Debug, Subcommand)]
pub enum ShardCommand {
    /// Join the folders of every shard of one `--shard I/N` study into the tables and plots
    /// one process would have written.
    Merge(crate::arg_groups::MergeArgs),
}

#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct EvalArgs {
    #[command(subcommand)]
    pub command: Option<ShardCommand>,
    #[command(flatten)]
    pub input: InputArgs,
    /// Image width (overrides `[image] width`; 0: the frame's own).
    #[arg(long)]
    pub width: Option<usize>,
    /// Image height (overrides `[image] height`; 0: the frame's own).
    #[arg(long)]
    pub height: Option<usize>,
    /// Resize interpolation (overrides `[image] interpolation`).
    #[arg(long)]
    pub interpolation: Option<String>,
    /// The paper's figure quartiles (`paper-figure-medians.tsv`: figure, combination, q1,
    /// median, q3) to print beside ours.
    #[arg(long)]
    pub paper: Option<PathBuf>,
    /// The paper authors' per-image results (a folder of `DETECTOR_DESCRIPTOR.csv`:
    /// image_number, evaluation_1 … evaluation_6): writes reference.csv/.md holding keylo's
    /// results against theirs image by image (images matched by the number in their names).
    #[arg(long, value_name = "DIR")]
    pub reference: Option<PathBuf>,
    /// Draw each detector's keypoints (circles of their size, lines along their orientation)
    /// on images 0, N, 2N, … as evaluated, into OUT/images/DETECTOR_NNNNN.png.
    #[arg(long, value_name = "EVERY_N", conflicts_with = "shard", value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub images: Option<usize>,
}

#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    pub command: Option<ShardCommand>,
    #[command(flatten)]
    pub input: InputArgs,
    /// Interpolations (comma-separated; default: all five).
    #[arg(long, default_value = "cubic,lanczos4,area,nearest,linear")]
    pub interpolations: String,
    /// Widths: MIN:MAX:STEP or a list (the paper: 512:4096:128).
    #[arg(long, default_value = "512:4096:128")]
    pub widths: String,
    /// Heights: MIN:MAX:STEP or a list (the paper: 32:256:32).
    #[arg(long, default_value = "32:256:32")]
    pub heights: String,
}

pub fn run(cmd: KeypointsCommand, threads: Option<usize>, quiet: bool) -> Result<ExitCode> {
    match cmd {
        KeypointsCommand::Eval(EvalArgs {
            command: Some(ShardCommand::Merge(m)),
            ..
        }) => shards::eval_merge(&m, quiet),
        KeypointsCommand::Sweep(SweepArgs {
            command: Some(ShardCommand::Merge(m)),
            ..
        }) => shards::sweep_merge(&m, quiet),
        KeypointsCommand::Eval(a) => eval::run(a, threads, quiet),
        KeypointsCommand::Sweep(a) => sweep::run(a, threads, quiet),
    }
}
