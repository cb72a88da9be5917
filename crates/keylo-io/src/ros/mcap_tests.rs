use std::collections::BTreeMap;
use std::io::Cursor;

use mcap::records::{op, MessageHeader};

use super::*;

/// An mcap with channels 1 (/a) and 2 (/b), one message per `(channel, log_time)`, chunks of
/// about `chunk` bytes (messages are 100 bytes of noise so chunks do not shrink much).
fn mcap_bytes(msgs: &[(u16, u64)], chunk: u64) -> Vec<u8> {
    mcap_bytes_with(msgs, chunk, Some(mcap::Compression::Zstd))
}

fn mcap_bytes_with(
    msgs: &[(u16, u64)],
    chunk: u64,
    compression: Option<mcap::Compression>,
) -> Vec<u8> {
    let opts = mcap::WriteOptions::new()
        .compression(compression)
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

/// Offsets and opcodes of the top-level records (after the start magic).
fn top_records(bytes: &[u8]) -> Vec<(usize, u8)> {
    let mut out = Vec::new();
    let mut at = 8;
    while at + 9 <= bytes.len() {
        let len = u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap()) as usize;
        out.push((at, bytes[at]));
        if bytes[at] == op::FOOTER {
            break;
        }
        at += 9 + len;
    }
    out
}

#[test]
fn file_order_reads_every_message_and_checks_the_data_section_crc() {
    let bytes = mcap_bytes(&messages(), 1000);
    let records = top_records(&bytes);
    let (data_end, _) = *records.iter().find(|r| r.1 == op::DATA_END).unwrap();
    // Cut after the data end record: no footer, so the file is read in file order.
    let cut = &bytes[..data_end + 9 + 4];
    let (_d, mut f) = open(cut);
    assert!(f.note().unwrap().contains("summary"), "{:?}", f.note());
    let got = read_all(&mut f, "/a");
    assert_eq!(got.iter().filter(|r| r.is_ok()).count(), 21);
    let err = got.last().unwrap().as_ref().unwrap_err();
    assert!(err.contains("before its footer"), "{err}");

    // A changed byte in the header record (outside every chunk): only the data section CRC
    // sees it, once every message has been read.
    let mut bad = cut.to_vec();
    let last = records[1].0 - 1; // the header record's last byte (its library string)
    bad[last] ^= 0x01;
    let (_d, mut f) = open(&bad);
    let got = read_all(&mut f, "/a");
    assert_eq!(got.iter().filter(|r| r.is_ok()).count(), 21);
    let err = got.last().unwrap().as_ref().unwrap_err();
    assert!(err.contains("data section CRC mismatch"), "{err}");
}

#[test]
fn file_order_reads_give_a_chunks_messages_before_its_bad_record() {
    // One uncompressed chunk; its CRC zeroed (not checked), its third message moved to an
    // unknown channel; cut after the data end record, so it is read in file order.
    let mut bytes = mcap_bytes_with(&messages(), 1 << 20, None);
    let records = top_records(&bytes);
    let (chunk, _) = *records.iter().find(|r| r.1 == op::CHUNK).unwrap();
    let (data_end, _) = *records.iter().find(|r| r.1 == op::DATA_END).unwrap();
    bytes.truncate(data_end + 9 + 4);
    bytes[chunk + 33..chunk + 37].fill(0);
    // Opcode, length, start, end, size, CRC, compression "" (4), compressed size: the records.
    let start = chunk + 9 + 8 + 8 + 8 + 4 + 4 + 8;
    let mut at = start;
    let mut seen = 0;
    while seen < 3 {
        if bytes[at] == op::MESSAGE {
            seen += 1;
        }
        if seen < 3 {
            at += 9 + u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap()) as usize;
        }
    }
    bytes[at + 9..at + 11].copy_from_slice(&99u16.to_le_bytes());
    let (_d, mut f) = open(&bytes);
    let got = read_all(&mut f, "/a");
    assert_eq!(got.len(), 2, "{got:?}");
    assert_eq!(got[0], Ok(0));
    let err = got[1].as_ref().unwrap_err();
    let want = format!(
        "chunk at byte {chunk}: record at byte {} of its records",
        at - start
    );
    assert!(err.contains(&want) && err.contains("channel 99"), "{err}");
}
