//! A capture whose lidar datagrams arrive as IP fragments (the usual case for 128-beam
//! sensors on a 1500-byte MTU) decodes to the same frames as the unfragmented capture.

use std::fs::File;
use std::path::{Path, PathBuf};

use keylo_core::{BuildContext, ImageSource, LidarFrame};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};
use pcap_file::pcap::{PcapPacket, PcapReader, PcapWriter};

const SAMPLE: &str = "OS-0-128_v3.0.1_1024x10_from_osf";

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ouster")
}

/// Splits the IPv4 payload of an Ethernet frame into fragments of at most `mtu` bytes of IP.
fn fragment(frame: &[u8], mtu: usize) -> Vec<Vec<u8>> {
    let (eth, ip) = frame.split_at(14);
    let header = usize::from(ip[0] & 0x0F) * 4;
    let body = &ip[header..];
    let chunk = (mtu - header) / 8 * 8;
    let pieces: Vec<&[u8]> = body.chunks(chunk).collect();
    let n = pieces.len();
    // Last fragment first, as some stacks send them, to exercise reordering.
    (0..n)
        .rev()
        .map(|k| {
            let mut f = eth.to_vec();
            let mut h = ip[..header].to_vec();
            h[2..4].copy_from_slice(&((header + pieces[k].len()) as u16).to_be_bytes());
            let flags = ((k * chunk / 8) as u16) | if k + 1 < n { 0x2000 } else { 0 };
            h[6..8].copy_from_slice(&flags.to_be_bytes());
            f.extend_from_slice(&h);
            f.extend_from_slice(pieces[k]);
            f
        })
        .collect()
}

fn frames(pcap: &Path) -> Vec<LidarFrame> {
    let config = OusterSourceConfig {
        path: pcap.display().to_string(),
        meta: fixtures()
            .join(format!("{SAMPLE}.json"))
            .display()
            .to_string(),
        ..OusterSourceConfig::default()
    };
    let ctx = BuildContext {
        base_dir: PathBuf::from("."),
        ..Default::default()
    };
    let mut s = OusterSource::open(&config, &ctx).unwrap();
    std::iter::from_fn(|| s.next_frame())
        .map(|f| f.unwrap())
        .collect()
}

#[test]
fn fragmented_datagrams_are_reassembled() {
    let original = fixtures().join(format!("{SAMPLE}.pcap"));
    let dir = tempfile::tempdir().unwrap();
    let fragmented = dir.path().join("fragmented.pcap");
    let mut reader = PcapReader::new(File::open(&original).unwrap()).unwrap();
    let header = reader.header();
    let mut writer = PcapWriter::with_header(File::create(&fragmented).unwrap(), header).unwrap();
    let mut split = 0;
    while let Some(p) = reader.next_packet() {
        let p = p.unwrap();
        let pieces = fragment(&p.data, 1500);
        split += usize::from(pieces.len() > 1);
        for piece in pieces {
            let len = piece.len() as u32;
            writer
                .write_packet(&PcapPacket::new(p.timestamp, len, &piece))
                .unwrap();
        }
    }
    drop(writer);
    assert!(split > 100, "only {split} datagrams were fragmented");
    let (a, b) = (frames(&original), frames(&fragmented));
    assert_eq!(a.len(), 2);
    assert_eq!(a, b);
}
