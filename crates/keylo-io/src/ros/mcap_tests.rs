use std::collections::BTreeMap;
use std::io::Cursor;

use mcap::records::MessageHeader;

use super::*;

/// An mcap with channels 1 (/a) and 2 (/b), one message per `(channel, log_time)`, chunks of
/// about `chunk` bytes (messages are 100 bytes of noise so chunks do not shrink much).
fn mcap_bytes(msgs: &[(u16, u64)], chunk: u64) -> Vec<u8> {
    let opts = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .chunk_size(Some(chunk));
    let mut w = opts.create(Cursor::new(Vec::new())).unwrap();
    let schema = w
        .add_schema("std_msgs/msg/String", "ros2msg", b"string data")
        .unwrap();
    let a = w
        .add_channel(schema, "/a", "cdr", &BTreeMap::new())
        .unwrap();
    let b = w
        .add_channel(schema, "/b", "cdr", &BTreeMap::new())
        .unwrap();
    for (i, &(ch, t)) in msgs.iter().enumerate() {
        let data: Vec<u8> = (0..100u32)
            .map(|k| (k * 7919 + i as u32 * 104_729) as u8)
            .collect();
        let channel_id = if ch == 1 { a } else { b };
        let header = MessageHeader {
            channel_id,
            sequence: i as u32,
            log_time: t,
            publish_time: t,
        };
        w.write_to_known_channel(&header, &data).unwrap();
    }
    w.finish().unwrap();
    w.into_inner().into_inner()
}

fn open(bytes: &[u8]) -> (tempfile::TempDir, McapFile) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.mcap");
    std::fs::write(&path, bytes).unwrap();
    let file = McapFile::open(&path).unwrap();
    (dir, file)
}

fn read_all(f: &mut McapFile, topic: &str) -> Vec<Result<u64, String>> {
    let ids: Vec<u32> = f
        .channels()
        .iter()
        .filter(|c| c.topic == topic)
        .map(|c| c.id)
        .collect();
    f.select(&ids);
    std::iter::from_fn(|| f.next_message())
        .map(|r| r.map(|m| m.log_time).map_err(|e| e.to_string()))
        .collect()
}

fn messages() -> Vec<(u16, u64)> {
    // Written out of log-time order on purpose: /a's 15 comes after 20.
    let mut m: Vec<(u16, u64)> = (0..40).map(|i| (1 + (i % 2) as u16, 10 * i)).collect();
    m.insert(5, (1, 15));
    m
}

#[test]
fn indexed_files_read_in_log_time_order() {
    let bytes = mcap_bytes(&messages(), 1000);
    let (_d, mut f) = open(&bytes);
    assert_eq!(f.note(), None);
    let chans: Vec<_> = f
        .channels()
        .iter()
        .map(|c| (c.topic.as_str(), c.msg_type.as_str(), c.count, c.encoding))
        .collect();
    assert_eq!(
        chans,
        vec![
            ("/a", "std_msgs/msg/String", Some(21), Some(Encoding::Cdr)),
            ("/b", "std_msgs/msg/String", Some(20), Some(Encoding::Cdr))
        ]
    );
    assert_eq!(f.time_range(), Some((0, 390)));
    let times: Vec<u64> = read_all(&mut f, "/a")
        .into_iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(times.len(), 21);
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    assert_eq!(&times[..3], &[0, 15, 20]);
}

/// Offset of the `n`-th chunk record, from the file's own index.
fn chunk_offset(bytes: &[u8], n: usize) -> usize {
    let (_d, f) = open(bytes);
    match &f.mode {
        Mode::Indexed { chunks, .. } => {
            let mut pos: Vec<u64> = chunks.iter().map(|c| c.span.pos).collect();
            pos.sort();
            pos[n] as usize
        }
        Mode::Linear { .. } => panic!("expected an indexed file"),
    }
}

#[test]
fn a_bad_chunk_crc_fails_that_chunk_after_the_ones_before() {
    let mut bytes = mcap_bytes(&messages(), 1000);
    let third = chunk_offset(&bytes, 2);
    // opcode 1 + length 8 + start 8 + end 8 + uncompressed size 8 = the CRC at +33.
    bytes[third + 33] ^= 0xff;
    let (_d, mut f) = open(&bytes);
    let got = read_all(&mut f, "/a");
    assert!(got[0].is_ok());
    let err = got.last().unwrap().as_ref().unwrap_err();
    assert!(err.contains(&format!("chunk at byte {third}")), "{err}");
    assert!(err.to_lowercase().contains("crc"), "{err}");
}

#[test]
fn truncated_files_are_read_in_file_order_up_to_the_cut() {
    let bytes = mcap_bytes(&messages(), 1000);
    let third = chunk_offset(&bytes, 2);
    let (_d, mut f) = open(&bytes[..third + 50]);
    assert!(f.note().unwrap().contains("summary"), "{:?}", f.note());
    let a = f.channels().iter().find(|c| c.topic == "/a").unwrap();
    assert!(a.count.unwrap() > 0);
    let got = read_all(&mut f, "/a");
    assert!(got.len() > 2);
    assert!(got[..got.len() - 1].iter().all(Result::is_ok));
    let err = got.last().unwrap().as_ref().unwrap_err();
    assert!(
        err.contains("near byte") && err.contains("messages before it were read"),
        "{err}"
    );
    // Reading again starts over.
    assert_eq!(read_all(&mut f, "/a").len(), got.len());
}
