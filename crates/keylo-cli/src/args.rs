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
    /// Show what a data path holds; with --image N, write frame N's channel images as PNG
    /// (with --config, its keypoints, registered pixels and a top view).
    Info(InfoArgs),
    /// Write the frames of any source as KITTI .bin, PLY, PCD or a keylo frame folder.
    Convert(ConvertArgs),
    /// Run several configs (and a grid of overrides) on the same data; tables and plots.
    Compare(CompareArgs),
    /// One self-contained report.html of a run or compare folder: tables, plots, pictures
    /// and 3-D views of the map, trajectories and points (opens offline).
    Report(ReportArgs),
    /// Inspect configs and the registered backends.
    #[command(subcommand)]
    Config(ConfigCommand),
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

#[derive(Debug, Args)]
pub struct RunArgs {
    /// Pipeline config (TOML); see docs/config.md.
    pub config: Option<PathBuf>,
    /// Data to read instead of `[source]` (kind auto-detected).
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Sensor metadata of the data (an Ouster capture's JSON when it is not X.json beside
    /// X.pcap).
    #[arg(long)]
    pub meta: Option<PathBuf>,
    /// Ground-truth trajectory (TUM or KITTI) for accuracy figures.
    #[arg(long)]
    pub gt: Option<PathBuf>,
    #[command(flatten)]
    pub reference: crate::reference_args::ReferenceArgs,
    /// Output directory (default: `[output] dir`, else runs/<timestamp>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a config value, e.g. --set registrar.voxel_size=0.5 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Frames read ahead on a thread of their own while the current one is registered;
    /// 0 reads each frame when it is needed. Results are the same either way.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(0..=16))]
    pub prefetch: u8,
    /// Play the data back at the sensor's rate: each frame is released at its timestamp
    /// (SPEED × real time; no value: 1), as a live sensor delivers it, so the CPU and memory
    /// figures are those at that rate (the paper's measure). Results are the same; the summary
    /// counts the frames released late (odometry did not keep up).
    #[arg(long, value_name = "SPEED", num_args = 0..=1, default_missing_value = "1")]
    pub realtime: Option<f64>,
    /// Pictures of frames 0, N, 2N, … in OUT/images/: each detector image with its
    /// keypoints and the pixels whose points were registered, and a top view of the raw and
    /// registered points; the first pictured frame also as PLY clouds (`keylo report`
    /// shows them).
    #[arg(long, value_name = "EVERY_N", value_parser = clap::value_parser!(u64).range(1..))]
    pub images: Option<u64>,
    /// Save a global map of the run in DIR: the world-frame cloud, voxelised (map.ply,
    /// map.pcd), and keyframes with their clouds, keypoints and descriptors; settings in
    /// `[map]` (docs/maps.md).
    #[arg(long, value_name = "DIR")]
    pub map_out: Option<PathBuf>,
}

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

#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Estimated trajectory (TUM or KITTI).
    #[arg(long)]
    pub est: PathBuf,
    /// Reference trajectory (TUM or KITTI).
    #[arg(long)]
    pub gt: PathBuf,
    #[command(flatten)]
    pub reference: crate::reference_args::ReferenceArgs,
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

#[derive(Debug, Args)]
pub struct InfoArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// Write the channel images of frame N (0-based) as PNG into --out.
    #[arg(long, value_name = "N", requires = "out")]
    pub image: Option<usize>,
    /// Folder for the PNG images of --image.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// With --image: run this pipeline config's stages on frame N and draw, as `keylo run
    /// --images` does, each detector image with its keypoints and the pixels whose points
    /// are registered, and a top view of the raw and registered points.
    #[arg(long, requires = "image")]
    pub config: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ConvertFormat {
    /// KITTI velodyne .bin: x y z + one channel (float32), in velodyne/.
    KittiBin,
    /// Binary little-endian PLY, one file per frame.
    Ply,
    /// Binary PCD v0.7, one file per frame.
    Pcd,
    /// keylo frame folder (every channel, the organised grid).
    Frames,
}

#[derive(Debug, Args)]
pub struct ConvertArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: ConvertFormat,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
    /// Per-point values besides x y z: signal, reflectivity, near-ir, range, ring, time
    /// (comma separated). PLY/PCD default: signal,reflectivity,near-ir,range,ring,time;
    /// KITTI .bin takes exactly one (default signal).
    #[arg(long, value_delimiter = ',')]
    pub channels: Vec<String>,
}

#[derive(Debug, Args)]
pub struct ReportArgs {
    /// A run folder (`keylo run --out DIR`) or a compare folder (`keylo compare --out DIR`).
    pub dir: PathBuf,
    /// The page to write (default: DIR/report.html).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Points per 3-D layer at most: larger clouds are thinned (one point in k) and the page
    /// says so.
    #[arg(long, default_value_t = 150_000, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub max_points: usize,
    /// Pictured frames (`keylo run --images`) shown at most, spread over the run.
    #[arg(long, default_value_t = 8, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub max_pictures: usize,
}
