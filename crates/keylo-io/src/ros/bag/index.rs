//! What a ROS1 bag holds, from its index section (connections and chunk infos) or, when the
//! index is missing or unreadable (a truncated file, a recording that was never closed), from
//! one scan over the chunks that decompresses each in turn. The scan stops at the first
//! unreadable record and keeps everything before it.

use std::fs::File;
use std::io::{BufReader, Seek, SeekFrom};
use std::path::Path;

use super::record::{decompress, op, records_in, Fields, Record};
use crate::ros::merge::ChunkSpan;
use crate::IoError;

const MAGIC: &[u8] = b"#ROSBAG V2.0\n";

/// A connection: the topic and type messages are stored under.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Connection {
    pub id: u32,
    pub topic: String,
    pub msg_type: String,
}

/// A chunk and the messages each connection has in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ChunkEntry {
    pub span: ChunkSpan,
    pub counts: Vec<(u32, u32)>,
}

/// Connections and chunks of a bag.
#[derive(Debug, Default)]
pub(crate) struct BagIndex {
    pub connections: Vec<Connection>,
    pub chunks: Vec<ChunkEntry>,
    /// Set when the index could not be used and the chunks were scanned.
    pub note: Option<String>,
    /// Where the scan stopped on damage: reported after the last readable message.
    pub damage: Option<String>,
}

type BagReader = BufReader<File>;

/// Reads the index of the bag at `path`, open as `file` (`len` bytes).
pub(crate) fn read_index(path: &Path, file: &mut BagReader, len: u64) -> Result<BagIndex, IoError> {
    let fail = |m: String| IoError::format(path, m);
    let mut magic = [0u8; MAGIC.len()];
    std::io::Read::read_exact(file, &mut magic).map_err(|e| IoError::io(path, e))?;
    if magic != MAGIC {
        return Err(fail("not a ROS1 bag 2.0 (no `#ROSBAG V2.0` line)".into()));
    }
    let at = MAGIC.len() as u64;
    let header = Record::read(file, len - at)
        .and_then(|r| r.ok_or_else(|| "the file ends after the version line".to_string()))
        .map_err(|e| fail(format!("bag header record at byte {at}: {e}")))?;
    let f = header
        .fields()
        .map_err(|e| fail(format!("bag header record at byte {at}: {e}")))?;
    let bag_header = (|| {
        if f.op()? != op::BAG_HEADER {
            return Err(format!(
                "expected a bag header record (op 3), found op {}",
                f.op()?
            ));
        }
        Ok((
            f.u64("index_pos")?,
            f.u32("conn_count")?,
            f.u32("chunk_count")?,
        ))
    })();
    let (index_pos, conns, chunks) =
        bag_header.map_err(|e| fail(format!("bag header record at byte {at}: {e}")))?;
    let data_start = stream_pos(path, file)?;
    let why_scan = if index_pos < data_start || index_pos >= len {
        format!("no index (index_pos {index_pos}, file of {len} bytes: truncated or never closed)")
    } else {
        match read_index_section(file, index_pos, len, (conns, chunks), data_start) {
            Ok(index) => return Ok(index),
            Err(e) => format!("index unreadable ({e})"),
        }
    };
    let end = if (data_start..len).contains(&index_pos) {
        index_pos
    } else {
        len
    };
    let mut index = scan(path, file, data_start, end)?;
    index.note = Some(format!("{why_scan}; read by scanning the chunks"));
    Ok(index)
}

fn stream_pos(path: &Path, file: &mut BagReader) -> Result<u64, IoError> {
    file.stream_position().map_err(|e| IoError::io(path, e))
}

fn read_index_section(
    file: &mut BagReader,
    index_pos: u64,
    len: u64,
    (conn_count, chunk_count): (u32, u32),
    data_start: u64,
) -> Result<BagIndex, String> {
    file.seek(SeekFrom::Start(index_pos))
        .map_err(|e| e.to_string())?;
    let mut index = BagIndex::default();
    let mut pos = index_pos;
    while let Some(rec) = Record::read(file, len - pos).map_err(|e| format!("byte {pos}: {e}"))? {
        let at = pos;
        pos += 8 + (rec.header.len() + rec.data.len()) as u64;
        let f = rec.fields().map_err(|e| format!("byte {at}: {e}"))?;
        let entry = match f.op() {
            Ok(op::CONNECTION) => connection(&f, &rec.data).map(|c| index.connections.push(c)),
            Ok(op::CHUNK_INFO) => {
                chunk_info(&f, &rec.data, data_start..index_pos).map(|c| index.chunks.push(c))
            }
            Ok(other) => Err(format!("unexpected record op {other} in the index section")),
            Err(e) => Err(e),
        };
        entry.map_err(|e| format!("record at byte {at}: {e}"))?;
    }
    if index.connections.len() != conn_count as usize || index.chunks.len() != chunk_count as usize
    {
        return Err(format!(
            "it lists {} connections and {} chunks, the bag header says {conn_count} and {chunk_count}",
            index.connections.len(),
            index.chunks.len()
        ));
    }
    Ok(index)
}

fn connection(f: &Fields, data: &[u8]) -> Result<Connection, String> {
    let inner = Fields::parse(data)?;
    Ok(Connection {
        id: f.u32("conn")?,
        topic: f.str("topic")?.to_string(),
        msg_type: inner.str("type")?.to_string(),
    })
}

fn chunk_info(
    f: &Fields,
    data: &[u8],
    chunk_section: std::ops::Range<u64>,
) -> Result<ChunkEntry, String> {
    let ver = f.u32("ver")?;
    if ver != 1 {
        return Err(format!("chunk info version {ver}, expected 1"));
    }
    let pos = f.u64("chunk_pos")?;
    if !chunk_section.contains(&pos) {
        return Err(format!(
            "chunk_pos {pos} lies outside the chunk section {chunk_section:?}"
        ));
    }
    let count = f.u32("count")? as usize;
    if data.len() != count.saturating_mul(8) {
        return Err(format!(
            "{count} entries need {} bytes, found {}",
            count * 8,
            data.len()
        ));
    }
    let counts = data
        .chunks_exact(8)
        .map(|e| {
            let n = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            (n(&e[..4]), n(&e[4..]))
        })
        .collect();
    let (start, end) = (f.time("start_time")?, f.time("end_time")?);
    Ok(ChunkEntry {
        span: ChunkSpan {
            pos,
            length: 0,
            start,
            end,
        },
        counts,
    })
}

/// Scans the chunk section `[start, end)`; a damaged record ends the scan (`damage`).
fn scan(path: &Path, file: &mut BagReader, start: u64, end: u64) -> Result<BagIndex, IoError> {
    file.seek(SeekFrom::Start(start))
        .map_err(|e| IoError::io(path, e))?;
    let mut index = BagIndex::default();
    let mut pos = start;
    while pos < end {
        let rec = match Record::read(file, end - pos) {
            Ok(Some(rec)) => rec,
            Ok(None) => break,
            Err(e) => {
                index.damage = Some(format!("record at byte {pos}: {e}"));
                break;
            }
        };
        let at = pos;
        pos += 8 + (rec.header.len() + rec.data.len()) as u64;
        match scan_record(&rec, at, &mut index) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                index.damage = Some(format!("chunk at byte {at}: {e}"));
                break;
            }
        }
    }
    Ok(index)
}

/// Adds a chunk's connections and message counts; `false` at the index section.
fn scan_record(rec: &Record, at: u64, index: &mut BagIndex) -> Result<bool, String> {
    let f = rec.fields()?;
    match f.op()? {
        op::CHUNK => {}
        op::CONNECTION | op::CHUNK_INFO => return Ok(false),
        _ => return Ok(true), // index data of the chunk before
    }
    let plain = decompress(f.str("compression")?, &rec.data, f.u32("size")?)?;
    let mut counts: Vec<(u32, u32)> = Vec::new();
    let (mut start, mut end) = (u64::MAX, 0);
    for inner in records_in(&plain) {
        let (_, fields, data) = inner?;
        match fields.op()? {
            op::CONNECTION => {
                let c = connection(&fields, data)?;
                if !index.connections.iter().any(|k| k.id == c.id) {
                    index.connections.push(c);
                }
            }
            op::MSG_DATA => {
                let (conn, t) = (fields.u32("conn")?, fields.time("time")?);
                (start, end) = (start.min(t), end.max(t));
                match counts.iter_mut().find(|(c, _)| *c == conn) {
                    Some((_, n)) => *n += 1,
                    None => counts.push((conn, 1)),
                }
            }
            _ => {}
        }
    }
    if !counts.is_empty() {
        index.chunks.push(ChunkEntry {
            span: ChunkSpan {
                pos: at,
                length: 0,
                start,
                end,
            },
            counts,
        });
    }
    Ok(true)
}
