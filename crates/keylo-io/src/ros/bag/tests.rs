use super::record::tests::record;
use super::*;

type Msg<'a> = (u32, u64, &'a [u8]);

fn time(ns: u64) -> [u8; 8] {
    (((ns % 1_000_000_000) << 32) | (ns / 1_000_000_000)).to_le_bytes()
}

fn connection(id: u32) -> Vec<u8> {
    let topic = format!("/t{id}");
    let inner = record(
        &[("topic", topic.as_bytes()), ("type", b"std_msgs/String")],
        b"",
    );
    // A connection's data is a field list without the record's data length prefix.
    let fields = &inner[4..inner.len() - 4];
    record(
        &[
            ("op", &[op::CONNECTION]),
            ("conn", &id.to_le_bytes()),
            ("topic", topic.as_bytes()),
        ],
        fields,
    )
}

fn bz2(data: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut e = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::fast());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

/// A bag with one chunk per entry of `chunks`; `indexed` writes the index section.
fn bag(chunks: &[Vec<Msg>], indexed: bool) -> Vec<u8> {
    let mut body = Vec::new();
    let mut infos = Vec::new();
    let mut seen = Vec::new();
    let start = 13
        + record(
            &[
                ("op", &[3]),
                ("index_pos", &[0; 8]),
                ("conn_count", &[0; 4]),
                ("chunk_count", &[0; 4]),
            ],
            &[0; 16],
        )
        .len();
    for msgs in chunks {
        let mut plain = Vec::new();
        for &(conn, t, data) in msgs {
            if !seen.contains(&conn) {
                seen.push(conn);
                plain.extend(connection(conn));
            }
            plain.extend(record(
                &[
                    ("op", &[op::MSG_DATA]),
                    ("conn", &conn.to_le_bytes()),
                    ("time", &time(t)),
                ],
                data,
            ));
        }
        let pos = (start + body.len()) as u64;
        let (lo, hi) = msgs
            .iter()
            .fold((u64::MAX, 0), |(a, b), m| (a.min(m.1), b.max(m.1)));
        let conns: Vec<u32> = seen
            .iter()
            .copied()
            .filter(|c| msgs.iter().any(|m| m.0 == *c))
            .collect();
        let mut entries = Vec::new();
        for c in &conns {
            entries.extend(c.to_le_bytes());
            entries.extend((msgs.iter().filter(|m| m.0 == *c).count() as u32).to_le_bytes());
        }
        infos.push(record(
            &[
                ("op", &[op::CHUNK_INFO]),
                ("ver", &1u32.to_le_bytes()),
                ("chunk_pos", &pos.to_le_bytes()),
                ("start_time", &time(lo)),
                ("end_time", &time(hi)),
                ("count", &(conns.len() as u32).to_le_bytes()),
            ],
            &entries,
        ));
        body.extend(record(
            &[
                ("op", &[op::CHUNK]),
                ("compression", b"bz2"),
                ("size", &(plain.len() as u32).to_le_bytes()),
            ],
            &bz2(&plain),
        ));
    }
    let index_pos = if indexed {
        (start + body.len()) as u64
    } else {
        0
    };
    if indexed {
        for &c in &seen {
            body.extend(connection(c));
        }
        body.extend(infos.concat());
    }
    let mut out = b"#ROSBAG V2.0\n".to_vec();
    out.extend(record(
        &[
            ("op", &[3]),
            ("index_pos", &index_pos.to_le_bytes()),
            ("conn_count", &(seen.len() as u32).to_le_bytes()),
            ("chunk_count", &(chunks.len() as u32).to_le_bytes()),
        ],
        &[b' '; 16],
    ));
    assert_eq!(out.len(), start);
    out.extend(body);
    out
}

fn open(bytes: &[u8]) -> (tempfile::TempDir, BagFile) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.bag");
    std::fs::write(&path, bytes).unwrap();
    let bag = BagFile::open(&path).unwrap();
    (dir, bag)
}

fn read_all(bag: &mut BagFile, channels: &[u32]) -> Vec<Result<(u32, u64), String>> {
    bag.select(channels);
    std::iter::from_fn(|| bag.next_message())
        .map(|r| {
            r.map(|m| (m.channel, m.log_time))
                .map_err(|e| e.to_string())
        })
        .collect()
}

fn chunks() -> Vec<Vec<Msg<'static>>> {
    vec![
        vec![(1, 10, b"a"), (2, 12, b"b"), (1, 30, b"c")],
        vec![(1, 20, b"d"), (2, 40, b"e")], // overlaps the first chunk in time
    ]
}

#[test]
fn indexed_bags_read_in_time_order_per_selection() {
    let (_d, mut bag) = open(&bag(&chunks(), true));
    assert_eq!(bag.note(), None);
    let topics: Vec<_> = bag
        .channels()
        .iter()
        .map(|c| (c.id, c.topic.as_str(), c.count))
        .collect();
    assert_eq!(topics, vec![(1, "/t1", Some(3)), (2, "/t2", Some(2))]);
    assert_eq!(bag.channels()[0].msg_type, "std_msgs/String");
    assert_eq!(bag.time_range(), Some((10, 40)));
    let ones: Vec<_> = read_all(&mut bag, &[1])
        .into_iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(ones, vec![(1, 10), (1, 20), (1, 30)]);
    assert_eq!(read_all(&mut bag, &[1, 2]).len(), 5);
    assert_eq!(read_all(&mut bag, &[2])[1], Ok((2, 40)));
}

#[test]
fn unindexed_and_truncated_bags_are_scanned() {
    let full = bag(&chunks(), true);
    let (_d, mut unindexed) = open(&bag(&chunks(), false));
    assert!(
        unindexed.note().unwrap().contains("no index"),
        "{:?}",
        unindexed.note()
    );
    assert_eq!(read_all(&mut unindexed, &[1]).len(), 3);

    // Cut the file inside the second chunk: the first chunk's messages, then the damage.
    let first_chunk_end = {
        let (_d, b) = open(&full);
        b.chunks[1].span.pos as usize
    };
    let (_d, mut cut) = open(&full[..first_chunk_end + 30]);
    assert!(cut.note().unwrap().contains("truncated"));
    let got = read_all(&mut cut, &[1]);
    assert_eq!(got[..2], [Ok((1, 10)), Ok((1, 30))]);
    let err = got[2].as_ref().unwrap_err();
    assert!(
        err.contains(&format!("record at byte {first_chunk_end}")),
        "{err}"
    );
    assert!(err.contains("messages before it were read"), "{err}");
    assert_eq!(got.len(), 3);
}

#[test]
fn a_corrupt_chunk_fails_after_the_chunks_before_it() {
    let mut bytes = bag(&chunks(), true);
    let second = {
        let (_d, b) = open(&bytes);
        b.chunks[1].span.pos as usize
    };
    // Overwrite the compressed data of the second chunk (after its ~60-byte header).
    for b in &mut bytes[second + 70..second + 90] {
        *b = 0xA5;
    }
    let (_d, mut bag) = open(&bytes);
    let got = read_all(&mut bag, &[1]);
    assert_eq!(got[0], Ok((1, 10)));
    let err = got.last().unwrap().as_ref().unwrap_err();
    assert!(
        err.contains(&format!("chunk at byte {second}")) && err.contains("bz2"),
        "{err}"
    );
}

#[test]
fn bad_headers_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.bag");
    std::fs::write(&path, b"#ROSBAG V2.0\n\x05\0\0").unwrap();
    let e = BagFile::open(&path).err().unwrap().to_string();
    assert!(e.contains("bag header record at byte 13"), "{e}");
    std::fs::write(&path, b"#ROSBAG V1.2\n").unwrap();
    assert!(BagFile::open(&path).is_err());
}
