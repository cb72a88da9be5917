//! What to stream and record.

use std::path::PathBuf;

/// Where the viewer listens and what it records.
#[derive(Debug, Clone)]
pub struct ViewOptions {
    /// `HOST:PORT` of the live WebSocket server (`None`: no live view). Port 0 takes a free one.
    pub serve: Option<String>,
    /// MCAP file to record (`None`: no recording). An existing file is replaced.
    pub record: Option<PathBuf>,
    /// The local map, the trajectory and the reference are sent every this many frames (and
    /// with the last frame): the map is the largest message by far.
    pub map_every: u64,
    /// The live view's large messages (scan, registered cloud, images, map) at most this many
    /// times a second of wall time; 0: every frame. Poses and figures go every frame, and the
    /// recording takes everything.
    pub max_hz: f64,
    /// The map does not change (a saved map to localise in): the recording holds it once, with
    /// the first frame; the live view still sends it every `map_every` frames, for viewers that
    /// connect later.
    pub fixed_map: bool,
    /// The world frame's name.
    pub world_frame: String,
    /// The sensor frame's name.
    pub sensor_frame: String,
}

impl Default for ViewOptions {
    fn default() -> Self {
        Self {
            serve: None,
            record: None,
            map_every: 10,
            max_hz: 10.0,
            fixed_map: false,
            world_frame: crate::topics::WORLD_FRAME.into(),
            sensor_frame: crate::topics::SENSOR_FRAME.into(),
        }
    }
}

/// What the viewer is told about the run: the recording's metadata `keylo` and attachment
/// `config.toml`, the images to advertise, the reference to draw.
#[derive(Debug, Clone, Default)]
pub struct RunInfo {
    /// The resolved config (TOML), attached to the recording as `config.toml`.
    pub config_toml: Option<String>,
    /// Where the config came from (a path, or "defaults").
    pub config_origin: String,
    /// The source's description.
    pub source: String,
    /// The command that made the run.
    pub command: String,
    /// The images the pipeline makes (advertised before the first frame, so a viewer can
    /// subscribe to them from the start).
    pub images: Vec<String>,
    /// The reference trajectory (ground truth) to draw beside the estimate.
    pub reference: Option<keylo_core::Trajectory>,
}
