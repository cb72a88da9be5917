//! Groups lidar packets into frames by frame id, as ouster-sdk's scan batcher does, keeping
//! only the packets of the sensor the metadata describes.

use std::path::{Path, PathBuf};

use super::datagrams::Datagrams;
use super::metadata::{in_column_window, OusterMetadata};
use super::packet::{PacketFormat, RawFrame};
use super::pcap::UdpReader;
use crate::IoError;

/// A frame and whether every column of the column window arrived.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchedFrame {
    pub frame: RawFrame,
    pub complete: bool,
}

/// Packets that were not used, by reason (reported when a capture yields no frame).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Skipped {
    /// UDP datagrams to another port than the lidar port.
    pub other_port: usize,
    /// Datagrams whose size is not the lidar packet size (IMU packets, other profiles).
    pub other_size: usize,
    /// Lidar packets of another sensor or session (serial number or init id differ).
    pub other_sensor: usize,
}

/// Reads the frames of an Ouster pcap or live stream, staggered, in arrival order.
pub struct Batcher {
    path: PathBuf,
    reader: Box<dyn Datagrams>,
    format: PacketFormat,
    window: (usize, usize),
    port: Option<u16>,
    identity: (Option<u32>, Option<u64>),
    current: Option<RawFrame>,
    /// A frame handed back with [`Self::recycle`], reused for the next frame id.
    spare: Option<RawFrame>,
    done: bool,
    skipped: Skipped,
}

impl Batcher {
    /// Opens `pcap` for the sensor described by `meta`. Lidar packets are those to `port`
    /// (any port when `None`) of the packet size of `meta`'s profile, from the sensor with
    /// `meta`'s serial number and init id (when the metadata and the packets carry them).
    pub fn open(pcap: &Path, meta: &OusterMetadata, port: Option<u16>) -> Result<Self, IoError> {
        Self::new(Box::new(UdpReader::open(pcap)?), pcap, meta, port)
    }

    /// A batcher of any datagram stream (`label` names it in messages), with the rules of
    /// [`Self::open`].
    pub fn new(
        reader: Box<dyn Datagrams>,
        label: &Path,
        meta: &OusterMetadata,
        port: Option<u16>,
    ) -> Result<Self, IoError> {
        let format = PacketFormat::new(meta).map_err(|m| IoError::format(label, m))?;
        Ok(Self {
            path: label.to_path_buf(),
            reader,
            format,
            window: meta.column_window,
            port,
            identity: (meta.init_id, meta.prod_sn),
            current: None,
            spare: None,
            done: false,
            skipped: Skipped::default(),
        })
    }

    /// Datagrams skipped so far.
    pub fn skipped(&self) -> Skipped {
        self.skipped
    }

    /// Hands a frame's buffers back for the next frame (no per-frame allocation and zeroing).
    pub fn recycle(&mut self, frame: RawFrame) {
        self.spare = Some(frame);
    }

    fn finish(&self, mut frame: RawFrame) -> BatchedFrame {
        frame.clear_missing_columns();
        let window = self.window;
        let complete = frame
            .column_valid
            .iter()
            .enumerate()
            .all(|(c, valid)| *valid || !in_column_window(window, c));
        BatchedFrame { frame, complete }
    }

    /// Whether a datagram is a lidar packet of our sensor; counts the others.
    fn accept(&mut self, port: u16, payload: &[u8]) -> bool {
        if self.port.is_some_and(|p| p != port) {
            self.skipped.other_port += 1;
            return false;
        }
        if payload.len() != self.format.packet_size() {
            self.skipped.other_size += 1;
            return false;
        }
        if let Some((init_id, sn)) = self.format.identity(payload) {
            let (want_id, want_sn) = self.identity;
            if want_id.is_some_and(|w| w != init_id) || want_sn.is_some_and(|w| w != sn) {
                self.skipped.other_sensor += 1;
                return false;
            }
        }
        true
    }

    /// The next frame; `None` at the end of the capture. After an error (a truncated or
    /// corrupt capture) the batcher stops: frames before it were already returned.
    pub fn next_frame(&mut self) -> Option<Result<BatchedFrame, IoError>> {
        while !self.done {
            let datagram = match self.reader.next_datagram() {
                None => {
                    self.done = true;
                    break;
                }
                Some(Err(e)) => {
                    self.done = true;
                    self.current = None;
                    return Some(Err(e));
                }
                Some(Ok(d)) => d,
            };
            if !self.accept(datagram.dst_port, &datagram.payload) {
                continue;
            }
            let id = self.format.frame_id(&datagram.payload);
            let finished = match &self.current {
                Some(f) if f.frame_id != id => self.current.take(),
                _ => None,
            };
            let (format, spare) = (&self.format, &mut self.spare);
            let frame = self.current.get_or_insert_with(|| match spare.take() {
                Some(mut f) => {
                    f.reuse(id);
                    f
                }
                None => format.new_frame(id),
            });
            self.format.decode_into(&datagram.payload, frame);
            if let Some(f) = finished {
                return Some(Ok(self.finish(f)));
            }
        }
        self.current.take().map(|f| Ok(self.finish(f)))
    }

    /// The error for a capture that held no lidar packet of this sensor: what it held instead.
    pub fn no_frames_error(&self) -> IoError {
        let s = self.skipped;
        let (id, sn) = self.identity;
        let mut msg = format!(
            "no lidar packet of this sensor ({} bytes per packet, profile {}",
            self.format.packet_size(),
            self.format.profile_name()
        );
        if let Some(p) = self.port {
            msg += &format!(", port {p}");
        }
        if let Some(sn) = sn {
            msg += &format!(", serial {sn}");
        }
        if let Some(id) = id {
            msg += &format!(", init id {id}");
        }
        msg += &format!(
            "); skipped {} datagrams to other ports, {} of other sizes, {} of other sensors \
             — is the metadata JSON the one of this capture?",
            s.other_port, s.other_size, s.other_sensor
        );
        IoError::format(&self.path, msg)
    }
}
