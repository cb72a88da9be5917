//! ROS1 bags (format 2.0), read with `std::io` and the `bzip2`/`lz4` codecs.
//!
//! Why not the `rosbag` crate (0.6.3): it memory-maps the whole file, panics (slice out of
//! range in `chunk_records`/`index_records`) on a bag whose header points past the end of the
//! file — every truncated bag and every `.bag.active` left by a crashed recording — and cannot
//! read chunks without the index, so nothing before a truncation could be recovered. The
//! format is four record types; reading them here keeps memory at one chunk, never panics on
//! input, and reads unindexed bags by scanning (see [`index`]).

mod index;
mod record;

use std::fs::File;
use std::io::{BufReader, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use super::file::{BagFormat, ChannelInfo, MessageFile, StoredMessage};
use super::merge::{ChunkSpan, TimeMerge};
use super::wire::Encoding;
use crate::IoError;
use index::{read_index, ChunkEntry};
use record::{decompress, op, records_in, Record};

/// An open ROS1 bag.
pub(crate) struct BagFile {
    path: PathBuf,
    file: BufReader<File>,
    len: u64,
    channels: Vec<ChannelInfo>,
    chunks: Vec<ChunkEntry>,
    note: Option<String>,
    damage: Option<String>,
    wanted: Vec<u32>,
    merge: TimeMerge,
    damage_reported: bool,
}

impl BagFile {
    /// Opens a bag and reads its index (or scans it when the index is unusable).
    pub fn open(path: &Path) -> Result<Self, IoError> {
        let f = File::open(path).map_err(|e| IoError::io(path, e))?;
        let len = f.metadata().map_err(|e| IoError::io(path, e))?.len();
        let mut file = BufReader::new(f);
        let index = read_index(path, &mut file, len)?;
        let mut channels: Vec<ChannelInfo> = index
            .connections
            .iter()
            .map(|c| ChannelInfo {
                id: c.id,
                topic: c.topic.clone(),
                msg_type: c.msg_type.clone(),
                encoding: Some(Encoding::Ros1),
                encoding_name: "ros1".into(),
                count: Some(count_of(&index.chunks, c.id)),
            })
            .collect();
        channels.sort_by_key(|c| c.id);
        Ok(Self {
            path: path.to_path_buf(),
            file,
            len,
            channels,
            chunks: index.chunks,
            note: index.note,
            damage: index.damage,
            wanted: Vec::new(),
            merge: TimeMerge::new(Vec::new()),
            damage_reported: true,
        })
    }

    /// The selected messages of the chunk at `span.pos`.
    fn load(&mut self, span: &ChunkSpan, out: &mut Vec<StoredMessage>) -> Result<(), IoError> {
        let pos = span.pos;
        let fail = |m: String| IoError::format(&self.path, format!("chunk at byte {pos}: {m}"));
        self.file
            .seek(SeekFrom::Start(pos))
            .map_err(|e| IoError::io(&self.path, e))?;
        let rec = Record::read(&mut self.file, self.len.saturating_sub(pos))
            .and_then(|r| r.ok_or_else(|| "the file ends here".to_string()))
            .map_err(fail)?;
        let plain = (|| {
            let f = rec.fields()?;
            if f.op()? != op::CHUNK {
                return Err(format!(
                    "expected a chunk record (op 5), found op {}",
                    f.op()?
                ));
            }
            decompress(f.str("compression")?, &rec.data, f.u32("size")?)
        })()
        .map_err(fail)?;
        for inner in records_in(&plain) {
            let (_, fields, data) = inner.map_err(fail)?;
            if fields.op().map_err(fail)? != op::MSG_DATA {
                continue;
            }
            let channel = fields.u32("conn").map_err(fail)?;
            if self.wanted.contains(&channel) {
                out.push(StoredMessage {
                    channel,
                    log_time: fields.time("time").map_err(fail)?,
                    data: data.to_vec(),
                });
            }
        }
        Ok(())
    }
}

fn count_of(chunks: &[ChunkEntry], conn: u32) -> u64 {
    chunks
        .iter()
        .flat_map(|c| &c.counts)
        .filter(|(c, _)| *c == conn)
        .map(|(_, n)| u64::from(*n))
        .sum()
}

impl MessageFile for BagFile {
    fn path(&self) -> &Path {
        &self.path
    }

    fn format(&self) -> BagFormat {
        BagFormat::Ros1Bag
    }

    fn channels(&self) -> &[ChannelInfo] {
        &self.channels
    }

    fn time_range(&self) -> Option<(u64, u64)> {
        let start = self.chunks.iter().map(|c| c.span.start).min()?;
        let end = self.chunks.iter().map(|c| c.span.end).max()?;
        Some((start, end))
    }

    fn note(&self) -> Option<&str> {
        self.note.as_deref()
    }

    fn damage(&self) -> Option<&str> {
        self.damage.as_deref()
    }

    fn select(&mut self, channels: &[u32]) {
        self.wanted = channels.to_vec();
        let spans = self
            .chunks
            .iter()
            .filter(|c| c.counts.iter().any(|(id, _)| channels.contains(id)))
            .map(|c| c.span)
            .collect();
        self.merge = TimeMerge::new(spans);
        self.damage_reported = false;
    }

    fn next_message(&mut self) -> Option<Result<StoredMessage, IoError>> {
        let mut merge = std::mem::replace(&mut self.merge, TimeMerge::new(Vec::new()));
        let next = merge.next(|span, out| self.load(span, out));
        self.merge = merge;
        match next {
            Some(Err(e)) => {
                self.damage_reported = true;
                Some(Err(e))
            }
            Some(ok) => Some(ok),
            None if !self.damage_reported => {
                self.damage_reported = true;
                let damage = self.damage.as_ref()?;
                Some(Err(IoError::format(
                    &self.path,
                    format!("{damage} (the messages before it were read)"),
                )))
            }
            None => None,
        }
    }
}

#[cfg(test)]
#[path = "tests.rs"]
mod tests;
