//! UDP payloads from a pcap capture (Ethernet + IPv4 + UDP), with the capture time.
//! IP fragments are reported as an error for now (the samples hold whole datagrams).

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use pcap_file::pcap::PcapReader;
use pcap_file::DataLink;

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
            match udp_of(&packet.data) {
                Ok(Some((dst_port, payload))) => {
                    return Some(Ok(Datagram {
                        time,
                        dst_port,
                        payload: payload.to_vec(),
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

/// `(destination port, payload)` of an Ethernet/IPv4/UDP frame; `None` for other traffic.
fn udp_of(frame: &[u8]) -> Result<Option<(u16, &[u8])>, String> {
    let be16 = |b: &[u8], at: usize| u16::from_be_bytes([b[at], b[at + 1]]);
    if frame.len() < 14 || be16(frame, 12) != 0x0800 {
        return Ok(None);
    }
    let ip = &frame[14..];
    if ip.len() < 20 || ip[9] != 17 {
        return Ok(None);
    }
    let header = usize::from(ip[0] & 0x0F) * 4;
    if be16(ip, 6) & 0x3FFF != 0 {
        return Err("IP-fragmented datagram: reassembly is not supported yet".into());
    }
    let total = usize::from(be16(ip, 2)).min(ip.len());
    if header < 20 || total < header + 8 {
        return Err("malformed IPv4/UDP header".into());
    }
    let udp = &ip[header..total];
    let udp_len = usize::from(be16(udp, 4)).clamp(8, udp.len());
    Ok(Some((be16(udp, 2), &udp[8..udp_len])))
}
