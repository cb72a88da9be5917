//! Groups lidar packets into frames by frame id, as ouster-sdk's scan batcher does.

use std::path::Path;

use super::metadata::OusterMetadata;
use super::packet::{PacketFormat, RawFrame};
use super::pcap::UdpReader;
use crate::IoError;

/// A frame and whether every column of the column window arrived.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchedFrame {
    pub frame: RawFrame,
    pub complete: bool,
}

/// Reads the frames of an Ouster pcap, staggered, in capture order.
pub struct Batcher {
    reader: UdpReader,
    format: PacketFormat,
    window: (usize, usize),
    current: Option<RawFrame>,
    done: bool,
}

impl Batcher {
    /// Opens `pcap` for the sensor described by `meta`.
    pub fn open(pcap: &Path, meta: &OusterMetadata) -> Result<Self, IoError> {
        let format = PacketFormat::new(meta).map_err(|m| IoError::format(pcap, m))?;
        Ok(Self {
            reader: UdpReader::open(pcap)?,
            format,
            window: meta.column_window,
            current: None,
            done: false,
        })
    }

    fn finish(&self, frame: RawFrame) -> BatchedFrame {
        let (first, last) = self.window;
        let complete = frame.column_valid[first..=last].iter().all(|v| *v);
        BatchedFrame { frame, complete }
    }

    /// The next frame; `None` at the end of the capture.
    pub fn next_frame(&mut self) -> Option<Result<BatchedFrame, IoError>> {
        while !self.done {
            let datagram = match self.reader.next_datagram() {
                None => {
                    self.done = true;
                    break;
                }
                Some(Err(e)) => return Some(Err(e)),
                Some(Ok(d)) => d,
            };
            if datagram.payload.len() != self.format.packet_size() {
                continue; // IMU or foreign packet
            }
            let id = self.format.frame_id(&datagram.payload);
            let finished = match &self.current {
                Some(f) if f.frame_id != id => self.current.take(),
                _ => None,
            };
            let frame = self
                .current
                .get_or_insert_with(|| self.format.new_frame(id));
            self.format.decode_into(&datagram.payload, frame);
            if let Some(f) = finished {
                return Some(Ok(self.finish(f)));
            }
        }
        self.current.take().map(|f| Ok(self.finish(f)))
    }
}
