//! `[source] kind = "ouster-udp"`: frames straight from an Ouster sensor's UDP packets, made
//! by the same batcher and destaggering as a pcap capture's (`kind = "ouster"`), so a capture
//! replayed onto the port gives the frames of `keylo run --data capture.pcap`, bit for bit.

use std::path::Path;
use std::time::Duration;

use keylo_core::BuildContext;
use serde::{Deserialize, Serialize};

use super::batcher::Batcher;
use super::live::LiveUdp;
use super::metadata::OusterMetadata;
use super::source::{return_of, OusterSource};
use crate::select::FrameSelection;
use crate::IoError;

/// `[source] kind = "ouster-udp"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct OusterUdpConfig {
    /// The sensor's metadata JSON (as ouster-sdk or the sensor's HTTP API
    /// `/api/v1/sensor/metadata` gives it); relative to the config file. Required.
    pub meta: String,
    /// Local address to receive on: `0.0.0.0` (every interface) or one interface's address.
    pub bind: String,
    /// UDP port of the lidar packets (the sensor's `udp_port_lidar`).
    pub lidar_port: u16,
    /// UDP port of the IMU packets (received and counted); 0: not bound.
    pub imu_port: u16,
    /// End the stream when no lidar packet came for this many seconds; 0: run until Ctrl-C /
    /// SIGTERM.
    pub idle_timeout_s: f64,
    /// Frames to read at most; 0: no limit.
    pub max_frames: usize,
    /// With dual-return profiles, the return that fills the frame: 1 = strongest, 2 = second.
    pub return_number: u8,
}

impl Default for OusterUdpConfig {
    fn default() -> Self {
        Self {
            meta: String::new(),
            bind: "0.0.0.0".into(),
            lidar_port: 7502,
            imu_port: 7503,
            idle_timeout_s: 0.0,
            max_frames: 0,
            return_number: 1,
        }
    }
}

impl OusterSource {
    /// Binds the ports of `config` and reads frames as the packets arrive; errors name the
    /// key or file that is wrong.
    pub fn open_udp(config: &OusterUdpConfig, ctx: &BuildContext) -> Result<Self, IoError> {
        if config.meta.is_empty() {
            return Err(IoError::format(
                Path::new("source.meta"),
                "no sensor metadata: set `[source] meta` to the sensor's metadata JSON",
            ));
        }
        if !(config.idle_timeout_s >= 0.0 && config.idle_timeout_s.is_finite()) {
            return Err(IoError::format(
                Path::new("source.idle_timeout_s"),
                format!("{}: expected seconds >= 0", config.idle_timeout_s),
            ));
        }
        let meta_path = ctx.resolve_path(&config.meta);
        let meta = OusterMetadata::read(&meta_path)?;
        let which = return_of(config.return_number, &meta, &meta_path)?;
        let idle =
            (config.idle_timeout_s > 0.0).then(|| Duration::from_secs_f64(config.idle_timeout_s));
        let live = LiveUdp::bind(&config.bind, config.lidar_port, config.imu_port, idle)?;
        let label = live.label().to_path_buf();
        let imu = live.imu_packets();
        let selection = FrameSelection::new(0, 1, config.max_frames)
            .map_err(|e| IoError::format(Path::new("source.max_frames"), e.to_string()))?;
        // Every datagram on the lidar port is a candidate: the port is the sensor's own.
        let batcher = Batcher::new(Box::new(live), &label, &meta, None)?;
        Ok(Self::live(
            label, meta_path, meta, batcher, which, selection, imu,
        ))
    }
}
