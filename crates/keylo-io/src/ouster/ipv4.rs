//! Ethernet/IPv4/UDP unwrapping with IP fragment reassembly (large Ouster packets exceed the
//! usual 1500-byte MTU and arrive as fragments unless the network uses jumbo frames).

use std::collections::HashMap;

/// A whole UDP datagram: destination port and payload.
pub type Udp = (u16, Vec<u8>);

/// Fragments of one IP datagram (keyed by source, destination, id).
#[derive(Default)]
struct Partial {
    /// `(byte offset, bytes)` of the fragments seen so far.
    pieces: Vec<(usize, Vec<u8>)>,
    /// Total length, known once the last fragment arrived.
    total: Option<usize>,
    /// Capture index of the first fragment (to drop stale datagrams).
    first_seen: usize,
}

/// Unwraps frames into UDP datagrams, joining IP fragments.
#[derive(Default)]
pub struct Reassembler {
    partial: HashMap<([u8; 4], [u8; 4], u16), Partial>,
    seen: usize,
}

/// Incomplete datagrams older than this many captured frames are dropped (a lost fragment).
const STALE_AFTER: usize = 4096;
/// Largest IPv4 datagram.
const MAX_DATAGRAM: usize = 65_535;

impl Reassembler {
    /// The UDP datagram this Ethernet frame completes, if any; `Ok(None)` for other traffic
    /// and for fragments still waiting for the rest. The error says what is malformed.
    pub(crate) fn push(&mut self, frame: &[u8]) -> Result<Option<Udp>, String> {
        self.seen += 1;
        let be16 = |b: &[u8], at: usize| u16::from_be_bytes([b[at], b[at + 1]]);
        if frame.len() < 14 || be16(frame, 12) != 0x0800 {
            return Ok(None);
        }
        let ip = &frame[14..];
        if ip.len() < 20 || ip[0] >> 4 != 4 || ip[9] != 17 {
            return Ok(None);
        }
        let header = usize::from(ip[0] & 0x0F) * 4;
        let total = usize::from(be16(ip, 2)).min(ip.len());
        if header < 20 || total < header {
            return Err("malformed IPv4 header".into());
        }
        let flags = be16(ip, 6);
        let more = flags & 0x2000 != 0;
        let offset = usize::from(flags & 0x1FFF) * 8;
        let body = &ip[header..total];
        if !more && offset == 0 {
            return udp(body).map(Some);
        }
        let key = (
            [ip[12], ip[13], ip[14], ip[15]],
            [ip[16], ip[17], ip[18], ip[19]],
            be16(ip, 4),
        );
        let seen = self.seen;
        let entry = self.partial.entry(key).or_insert_with(|| Partial {
            first_seen: seen,
            ..Partial::default()
        });
        if offset + body.len() > MAX_DATAGRAM {
            return Err(format!(
                "IP fragment past {MAX_DATAGRAM} bytes (offset {offset})"
            ));
        }
        entry.pieces.push((offset, body.to_vec()));
        if !more {
            entry.total = Some(offset + body.len());
        }
        let joined = entry.total.and_then(|t| join(&mut entry.pieces, t));
        let result = match joined {
            Some(datagram) => {
                self.partial.remove(&key);
                udp(&datagram).map(Some)
            }
            None => Ok(None),
        };
        self.partial
            .retain(|_, p| seen.saturating_sub(p.first_seen) < STALE_AFTER);
        result
    }
}

/// The datagram of `total` bytes when the pieces cover it without a gap.
fn join(pieces: &mut [(usize, Vec<u8>)], total: usize) -> Option<Vec<u8>> {
    pieces.sort_by_key(|(o, _)| *o);
    let mut out = vec![0u8; total];
    let mut covered = 0;
    for (offset, bytes) in pieces.iter() {
        if *offset > covered {
            return None;
        }
        let end = (offset + bytes.len()).min(total);
        if end > covered {
            out[covered..end].copy_from_slice(&bytes[covered - offset..end - offset]);
            covered = end;
        }
    }
    (covered == total).then_some(out)
}

/// `(destination port, payload)` of a whole UDP datagram (header included).
fn udp(datagram: &[u8]) -> Result<Udp, String> {
    if datagram.len() < 8 {
        return Err("UDP header truncated".into());
    }
    let port = u16::from_be_bytes([datagram[2], datagram[3]]);
    let len = usize::from(u16::from_be_bytes([datagram[4], datagram[5]])).clamp(8, datagram.len());
    Ok((port, datagram[8..len].to_vec()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ethernet + IPv4 frame of one fragment of a UDP datagram.
    pub(crate) fn fragment(id: u16, offset: usize, more: bool, body: &[u8]) -> Vec<u8> {
        let mut f = vec![0u8; 12];
        f.extend_from_slice(&[0x08, 0x00]);
        let total = (20 + body.len()) as u16;
        let flags = ((offset / 8) as u16) | if more { 0x2000 } else { 0 };
        f.extend_from_slice(&[0x45, 0]);
        f.extend_from_slice(&total.to_be_bytes());
        f.extend_from_slice(&id.to_be_bytes());
        f.extend_from_slice(&flags.to_be_bytes());
        f.extend_from_slice(&[64, 17, 0, 0, 10, 0, 0, 1, 10, 0, 0, 2]);
        f.extend_from_slice(body);
        f
    }

    fn datagram(port: u16, payload: &[u8]) -> Vec<u8> {
        let mut d = vec![0x1D, 0x4E];
        d.extend_from_slice(&port.to_be_bytes());
        d.extend_from_slice(&((payload.len() + 8) as u16).to_be_bytes());
        d.extend_from_slice(&[0, 0]);
        d.extend_from_slice(payload);
        d
    }

    #[test]
    fn whole_datagrams_pass_through() {
        let mut r = Reassembler::default();
        let frame = fragment(1, 0, false, &datagram(7502, b"abc"));
        assert_eq!(r.push(&frame).unwrap(), Some((7502, b"abc".to_vec())));
    }

    #[test]
    fn fragments_join_in_any_order_and_gaps_wait() {
        let payload: Vec<u8> = (0..3000u32).map(|i| i as u8).collect();
        let d = datagram(7502, &payload);
        let parts: Vec<_> = d.chunks(1480).collect();
        let frames: Vec<_> = parts
            .iter()
            .enumerate()
            .map(|(k, p)| fragment(9, k * 1480, k + 1 < parts.len(), p))
            .collect();
        let mut r = Reassembler::default();
        assert_eq!(r.push(&frames[2]).unwrap(), None);
        assert_eq!(r.push(&frames[0]).unwrap(), None);
        assert_eq!(r.push(&frames[1]).unwrap(), Some((7502, payload)));
        // A lost middle fragment never completes (and never panics).
        let mut r = Reassembler::default();
        assert_eq!(r.push(&frames[0]).unwrap(), None);
        assert_eq!(r.push(&frames[2]).unwrap(), None);
    }

    #[test]
    fn other_traffic_is_skipped_and_garbage_is_an_error() {
        let mut r = Reassembler::default();
        assert_eq!(r.push(&[0u8; 10]).unwrap(), None);
        let mut bad = fragment(1, 0, false, &[1, 2, 3]);
        bad[14] = 0x41; // IHL 1: header shorter than 20 bytes
        assert!(r.push(&bad).is_err());
        assert!(r.push(&fragment(1, 0, false, &[1, 2])).is_err());
    }
}
