//! Argument groups shared by several subcommands (flattened into each).

use std::path::PathBuf;

use clap::Args;
use keylo::config::Trust;

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

/// `--trust-plugins`: whether the libraries a config names itself may be loaded.
#[derive(Debug, Clone, Copy, Default, Args)]
pub struct TrustArgs {
    /// Load the libraries the config names itself (plugins in its `[plugins] dirs`, an
    /// `onnxruntime` path): their code runs. Without it such a config is refused before
    /// anything is loaded; plugins installed in KEYLO_PLUGIN_PATH or
    /// ~/.local/lib/keylo/plugins load either way (docs/plugins.md, "Trust").
    #[arg(long)]
    pub trust_plugins: bool,
}

impl TrustArgs {
    /// The trust the flag gives.
    pub fn trust(self) -> Trust {
        Trust::opted_in(self.trust_plugins)
    }
}

/// `--view`, `--record`: the run watched live and recorded (docs/report.md, "Watching a run
/// live").
#[derive(Debug, Clone, Default, Args)]
pub struct ViewArgs {
    /// Stream the run live to Foxglove or Lichtblick: a WebSocket server at HOST:PORT (no
    /// value: 127.0.0.1:8765) that the viewer's "Foxglove WebSocket" connection opens. The
    /// scan, registered cloud, local map, pose, trajectory, reference, images with keypoints
    /// and per-frame figures; a slow or closed viewer never holds the run up.
    #[arg(
        long,
        value_name = "HOST:PORT",
        num_args = 0..=1,
        default_missing_value = "127.0.0.1:8765"
    )]
    pub view: Option<String>,
    /// With --view: wait before the first frame until a viewer has connected (at most SECONDS;
    /// no value: until one does).
    #[arg(long, value_name = "SECONDS", num_args = 0..=1, default_missing_value = "inf")]
    pub view_wait: Option<f64>,
    /// Record the same streams as MCAP (Foxglove, Lichtblick; its scans are data for `keylo
    /// run --data FILE`), with the run's config attached. An existing file is replaced.
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
    /// With --view: the scan, registered cloud, images and map at most HZ times a second
    /// (default 10, a sensor's rate; 0: every frame); poses and figures go every frame, and
    /// --record takes everything.
    #[arg(long, value_name = "HZ")]
    pub view_hz: Option<f64>,
    /// Send the local map, the trajectory and the reference every N frames (and after the
    /// last; default 10): the map is the largest message.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub view_map_every: Option<u64>,
}
