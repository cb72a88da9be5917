//! `[source] kind = "ouster"`: frames of an Ouster pcap capture with its metadata JSON.

use std::path::{Path, PathBuf};

use keylo_core::{BuildContext, CoreError, ImageSource, LidarFrame, SourceInfo};
use serde::{Deserialize, Serialize};

use super::batcher::{BatchedFrame, Batcher};
use super::checks::check_frame;
use super::destagger::{Destaggerer, Return};
use super::metadata::{in_column_window, OusterMetadata};
use crate::select::FrameSelection;
use crate::IoError;

/// What happens to frames that miss columns of the column window.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum PartialFrames {
    /// Skip an incomplete first or last frame (the capture started or stopped mid-turn);
    /// keep incomplete frames in between, their missing columns invalid.
    #[default]
    SkipEnds,
    /// Keep every frame.
    Keep,
    /// Skip every incomplete frame.
    SkipAll,
}

/// `[source] kind = "ouster"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct OusterSourceConfig {
    /// The pcap capture; relative to the config file.
    pub path: String,
    /// The sensor metadata JSON; empty = `X.json` beside `X.pcap`. `--meta FILE` sets it.
    pub meta: String,
    /// Index of the first frame to read (after partial frames are skipped).
    pub start: usize,
    /// Read every `stride`-th frame.
    pub stride: usize,
    /// Frames to read at most; 0 = all.
    pub max_frames: usize,
    /// Frames missing columns: `skip-ends` (an incomplete first or last frame is dropped),
    /// `keep`, or `skip-all`.
    pub partial_frames: PartialFrames,
    /// With dual-return profiles, the return that fills the frame: 1 = strongest,
    /// 2 = second strongest.
    pub return_number: u8,
    /// UDP port of the lidar packets; 0 = the metadata's `udp_port_lidar`, or any port when
    /// the metadata has none.
    pub udp_port: u16,
}

impl Default for OusterSourceConfig {
    fn default() -> Self {
        Self {
            path: String::new(),
            meta: String::new(),
            start: 0,
            stride: 1,
            max_frames: 0,
            partial_frames: PartialFrames::SkipEnds,
            return_number: 1,
            udp_port: 0,
        }
    }
}

/// True for a `.pcap` file.
pub fn is_pcap(path: &Path) -> bool {
    path.is_file()
        && path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("pcap"))
}

/// The metadata of `pcap`: `meta` when given, else `X.json` beside `X.pcap`.
pub fn metadata_path(pcap: &Path, meta: Option<&Path>) -> Result<PathBuf, IoError> {
    if let Some(m) = meta {
        return Ok(m.to_path_buf());
    }
    let beside = pcap.with_extension("json");
    if beside.is_file() {
        Ok(beside)
    } else {
        Err(IoError::format(
            pcap,
            format!(
                "no sensor metadata: expected {} beside the capture, or give one with \
                 `--meta FILE` (`[source] meta`)",
                beside.display()
            ),
        ))
    }
}

/// `e` saying how many frames were read before it.
fn after_frame(e: CoreError, frames: usize) -> CoreError {
    match e {
        CoreError::Input { path, message } => CoreError::Input {
            path,
            message: format!("after {frames} frames: {message}"),
        },
        other => other,
    }
}

/// Reads an Ouster capture frame by frame (memory independent of the capture's length).
pub struct OusterSource {
    pcap: PathBuf,
    meta_path: PathBuf,
    meta: OusterMetadata,
    batcher: Batcher,
    destagger: Destaggerer,
    selection: FrameSelection,
    partial: PartialFrames,
    which: Return,
    /// The frame read ahead (to know whether the current one is the last).
    ahead: Option<Result<BatchedFrame, IoError>>,
    /// Whether frames are read ahead (a capture; a live stream hands each frame on at once).
    lookahead: bool,
    /// Lidar packets missing from the frames read (columns of the window never received).
    packets_lost: u64,
    /// Extra counters of the stream (live: IMU packets).
    imu_packets: Option<std::sync::Arc<std::sync::atomic::AtomicU64>>,
    /// Frames read from the capture so far (before selection).
    read: usize,
    /// Frames that passed the partial-frame rule so far (the index `start`/`stride` count).
    kept: usize,
    failed: bool,
}

impl OusterSource {
    /// Opens the capture and its metadata; errors name the file that is wrong.
    pub fn open(config: &OusterSourceConfig, ctx: &BuildContext) -> Result<Self, IoError> {
        if config.path.is_empty() {
            return Err(IoError::format(
                Path::new("source.path"),
                "no capture given: set `[source] path` or pass --data X.pcap",
            ));
        }
        let pcap = ctx.resolve_path(&config.path);
        let meta_arg = (!config.meta.is_empty()).then(|| ctx.resolve_path(&config.meta));
        let meta_path = metadata_path(&pcap, meta_arg.as_deref())?;
        let meta = OusterMetadata::read(&meta_path)?;
        let which = return_of(config.return_number, &meta, &meta_path)?;
        let selection = FrameSelection::new(config.start, config.stride, config.max_frames)
            .map_err(|m| IoError::format(Path::new("source.stride"), m))?;
        let port = match config.udp_port {
            0 => meta.udp_port_lidar,
            p => Some(p),
        };
        let mut batcher = Batcher::open(&pcap, &meta, port)?;
        let ahead = batcher.next_frame();
        if ahead.is_none() {
            return Err(batcher.no_frames_error());
        }
        Ok(Self {
            destagger: Destaggerer::new(&meta),
            pcap,
            meta_path,
            meta,
            batcher,
            selection,
            partial: config.partial_frames,
            which,
            ahead,
            lookahead: true,
            packets_lost: 0,
            imu_packets: None,
            read: 0,
            kept: 0,
            failed: false,
        })
    }

    /// A live stream's source: frames as they complete (no read-ahead), an incomplete first
    /// frame skipped (the stream started mid-turn), later incomplete ones kept with their
    /// missing columns invalid.
    pub(crate) fn live(
        label: PathBuf,
        meta_path: PathBuf,
        meta: OusterMetadata,
        batcher: Batcher,
        which: Return,
        selection: FrameSelection,
        imu_packets: std::sync::Arc<std::sync::atomic::AtomicU64>,
    ) -> Self {
        Self {
            destagger: Destaggerer::new(&meta),
            pcap: label,
            meta_path,
            meta,
            batcher,
            selection,
            partial: PartialFrames::SkipEnds,
            which,
            ahead: None,
            lookahead: false,
            packets_lost: 0,
            imu_packets: Some(imu_packets),
            read: 0,
            kept: 0,
            failed: false,
        }
    }

    /// The sensor metadata.
    pub fn metadata(&self) -> &OusterMetadata {
        &self.meta
    }

    /// The next frame that passes the partial-frame rule, with its capture index.
    fn next_kept(&mut self) -> Option<Result<BatchedFrame, IoError>> {
        loop {
            let current = if self.lookahead {
                self.ahead.take()?
            } else {
                match self.batcher.next_frame() {
                    Some(f) => f,
                    None if self.read == 0 => return Some(Err(self.batcher.no_frames_error())),
                    None => return None,
                }
            };
            let batched = match current {
                Ok(b) => b,
                Err(e) => return Some(Err(e)),
            };
            if let Err(msg) = check_frame(&batched.frame, &self.meta) {
                return Some(Err(IoError::format(&self.pcap, msg)));
            }
            if self.lookahead {
                self.ahead = self.batcher.next_frame();
            }
            let (first, last) = (self.read == 0, self.lookahead && self.ahead.is_none());
            self.read += 1;

            let skip = !batched.complete
                && match self.partial {
                    PartialFrames::Keep => false,
                    PartialFrames::SkipAll => true,
                    PartialFrames::SkipEnds => first || last,
                };
            if !skip {
                // Only frames handed on count: a skipped end frame was cut by the start or
                // end of the capture, not by lost packets.
                let lost = lost_packets(&batched.frame, &self.meta);
                if lost > 0 {
                    self.packets_lost += lost;
                    tracing::debug!(
                        "{}: frame id {}: {lost} packets lost ({} so far)",
                        self.pcap.display(),
                        batched.frame.frame_id,
                        self.packets_lost
                    );
                }
                return Some(Ok(batched));
            }
        }
    }
}

/// The return a config's `return_number` asks for, checked against the profile.
pub(crate) fn return_of(
    number: u8,
    meta: &OusterMetadata,
    meta_path: &Path,
) -> Result<Return, IoError> {
    match number {
        1 => Ok(Return::Strongest),
        2 if meta.udp_profile_lidar.returns() == 2 => Ok(Return::Second),
        2 => Err(IoError::format(
            meta_path,
            format!(
                "`source.return_number` = 2 but profile {} has one return",
                meta.udp_profile_lidar.name()
            ),
        )),
        n => Err(IoError::format(
            Path::new("source.return_number"),
            format!("{n}: expected 1 (strongest) or 2 (second strongest)"),
        )),
    }
}

/// Lidar packets a frame misses: columns of the column window never received, in packets.
fn lost_packets(frame: &super::packet::RawFrame, meta: &OusterMetadata) -> u64 {
    let missing = (frame.column_valid.iter().enumerate())
        .filter(|&(c, valid)| !valid && in_column_window(meta.column_window, c))
        .count();
    missing.div_ceil(meta.columns_per_packet.max(1)) as u64
}

impl ImageSource for OusterSource {
    fn info(&self) -> SourceInfo {
        SourceInfo {
            description: format!(
                "Ouster {} {} {} ({})",
                self.meta.prod_line,
                self.meta.lidar_mode,
                self.meta.udp_profile_lidar.name(),
                self.pcap.display()
            ),
            frames: None,
        }
    }

    fn details(&self) -> Vec<(String, String)> {
        let m = &self.meta;
        let or_unknown = |s: &str| {
            if s.is_empty() {
                "unknown".to_string()
            } else {
                s.to_string()
            }
        };
        let mut d = vec![
            ("sensor".into(), or_unknown(&m.prod_line)),
            (
                "serial".into(),
                m.prod_sn.map_or("unknown".into(), |s| s.to_string()),
            ),
            ("firmware".into(), or_unknown(&m.fw_rev)),
            ("lidar mode".into(), m.lidar_mode.clone()),
            ("UDP profile".into(), m.udp_profile_lidar.name().to_string()),
            ("returns".into(), m.udp_profile_lidar.returns().to_string()),
            (
                "column window".into(),
                match m.column_window {
                    (first, last) if first <= last => format!("{first}..={last}"),
                    (first, last) => {
                        format!("{first}..={}, 0..={last}", m.columns_per_frame - 1)
                    }
                },
            ),
            ("metadata".into(), self.meta_path.display().to_string()),
        ];
        if self.packets_lost > 0 {
            d.push(("packets lost".into(), self.packets_lost.to_string()));
        }
        let s = self.batcher.skipped();
        if s.other_port + s.other_size + s.other_sensor > 0 {
            d.push((
                "datagrams skipped".into(),
                format!(
                    "{} other port, {} other size (IMU, …), {} other sensor",
                    s.other_port, s.other_size, s.other_sensor
                ),
            ));
        }
        d
    }

    fn counters(&self) -> Vec<(String, u64)> {
        let s = self.batcher.skipped();
        let mut c = vec![
            ("packets_lost".to_string(), self.packets_lost),
            ("datagrams_other_size".to_string(), s.other_size as u64),
            ("datagrams_other_sensor".to_string(), s.other_sensor as u64),
            ("datagrams_other_port".to_string(), s.other_port as u64),
        ];
        if let Some(imu) = &self.imu_packets {
            c.push((
                "imu_packets".to_string(),
                imu.load(std::sync::atomic::Ordering::Relaxed),
            ));
        }
        c
    }

    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
        while !self.failed {
            if self.selection.past_end(self.kept) {
                return None;
            }
            let batched = match self.next_kept()? {
                Ok(b) => b,
                Err(e) => {
                    self.failed = true;
                    return Some(Err(after_frame(e.into(), self.kept)));
                }
            };
            let index = self.kept;
            self.kept += 1;
            let wanted = self.selection.wants(index);
            let frame = wanted.then(|| {
                self.destagger
                    .frame(&batched.frame, index as u64, self.which)
            });
            self.batcher.recycle(batched.frame);
            if let Some(frame) = frame {
                return Some(Ok(frame));
            }
        }
        None
    }
}
