//! `keylo run`'s arguments.

use std::path::PathBuf;

use clap::Args;

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
    #[command(flatten)]
    pub trust: crate::arg_groups::TrustArgs,
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
    #[command(flatten)]
    pub view: crate::arg_groups::ViewArgs,
}
