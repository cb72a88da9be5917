//! UDP payloads from a pcap capture (Ethernet + IPv4 + UDP, IP fragments joined), with the
//! capture time.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use pcap_file::pcap::PcapReader;
use pcap_file::DataLink;

use super::ipv4::Reassembler;
use crate::IoError;

/// One UDP datagram of the capture.
#[derive(Debug, Clone, PartialEq)]
pub struct Datagram {
    /// Capture time, seconds.
    pub time: f64,
    pub dst_port: u16,
    pub payload: Vec<u8>,
}

/// Iterates over the UDP datagrams of a pcap file.
pub struct UdpReader {
    path: PathBuf,
    reader: PcapReader<BufReader<File>>,
    index: usize,
    reassembler: Reassembler,
}

impl UdpReader {
    /// Opens a pcap file (Ethernet link type).
    pub fn open(path: &Path) -> Result<Self, IoError> {
        let file = File::open(path).map_err(|e| IoError::io(path, e))?;
        let reader = PcapReader::new(BufReader::new(file))
            .map_err(|e| IoError::format(path, format!("not a pcap capture: {e}")))?;
        if reader.header().datalink != DataLink::ETHERNET {
            return Err(IoError::format(
                path,
                format!(
                    "link type {:?}: only Ethernet captures are supported",
                    reader.header().datalink
                ),
            ));
        }
        Ok(Self {
            path: path.to_path_buf(),
            reader,
            index: 0,
            reassembler: Reassembler::default(),
        })
    }

    /// The next UDP datagram; non-UDP packets are skipped.
    pub fn next_datagram(&mut self) -> Option<Result<Datagram, IoError>> {
        loop {
            let packet = match self.reader.next_packet()? {
                Ok(p) => p,
                Err(e) => {
                    let msg = format!("packet {}: {e} (truncated capture?)", self.index);
                    return Some(Err(IoError::format(&self.path, msg)));
                }
            };
            self.index += 1;
            let time = packet.timestamp.as_secs_f64();
            match self.reassembler.push(&packet.data) {
                Ok(Some((dst_port, payload))) => {
                    return Some(Ok(Datagram {
                        time,
                        dst_port,
                        payload,
                    }))
                }
                Ok(None) => continue,
                Err(msg) => {
                    return Some(Err(IoError::format(
                        &self.path,
                        format!("packet {}: {msg}", self.index - 1),
                    )))
                }
            }
        }
    }
}
