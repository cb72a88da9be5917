//! MCAP files, read with keylo's own framing (`mcap_record`: every declared length is checked
//! against the bytes that are there before a buffer is allocated) and the `mcap` crate's record
//! parser; nothing is memory-mapped.
//!
//! With a summary (the normal case) the chunk indexes drive a lazy log-time merge: a chunk is
//! read, CRC-checked and decompressed when its messages are next. Without one (a truncated file,
//! a writer that was killed) the file is scanned once for channels and counts and then read in
//! file order; the scan stops at the first damage, and everything before it stays readable.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use super::file::{BagFormat, ChannelInfo, MessageFile, StoredMessage};
use super::mcap_chunk::chunk_messages;
use super::mcap_record::RECORD_LIMIT;
use super::mcap_stream::Linear;
use super::mcap_summary::{read_summary, McapSummary};
use super::merge::{ChunkSpan, TimeMerge};
use super::wire::Encoding;
use crate::IoError;

/// An indexed chunk: where it is and which channels it holds.
struct IndexedChunk {
    span: ChunkSpan,
    channels: Vec<u16>,
}

enum Mode {
    Indexed {
        chunks: Vec<IndexedChunk>,
        merge: TimeMerge,
    },
    Linear {
        stream: Option<Box<Linear>>,
    },
}

/// The file and what is read from its chunks.
struct Source {
    path: PathBuf,
    file: BufReader<File>,
    len: u64,
    wanted: Vec<u32>,
}

/// An open MCAP file.
pub(crate) struct McapFile {
    src: Source,
    channels: Vec<ChannelInfo>,
    time_range: Option<(u64, u64)>,
    note: Option<String>,
    /// Damage found by the scan of a file without summary (its stream reports it again).
    damage: Option<String>,
    mode: Mode,
    /// An error still to report once the current read runs out.
    deferred: Option<String>,
}

impl McapFile {
    /// Opens a file and reads its summary (or scans it when it has none).
    pub fn open(path: &Path) -> Result<Self, IoError> {
        let f = File::open(path).map_err(|e| IoError::io(path, e))?;
        let len = f.metadata().map_err(|e| IoError::io(path, e))?.len();
        let mut file = BufReader::new(f);
        let summary = read_summary(&mut file, len);
        let mut me = Self {
            src: Source {
                path: path.to_path_buf(),
                file,
                len,
                wanted: Vec::new(),
            },
            channels: Vec::new(),
            time_range: None,
            note: None,
            damage: None,
            mode: Mode::Linear { stream: None },
            deferred: None,
        };
        match summary {
            Ok(Some(s)) if !s.chunk_indexes.is_empty() => me.use_summary(&s),
            Ok(Some(_)) => me.scan("no chunk index (unchunked file)")?,
            Ok(None) => me.scan("no summary section")?,
            Err(e) => me.scan(&format!("summary unreadable ({e})"))?,
        }
        Ok(me)
    }

    fn use_summary(&mut self, s: &McapSummary) {
        let counts = s.stats.as_ref().map(|st| &st.channel_message_counts);
        self.channels = s
            .channels
            .iter()
            .map(|c| {
                let count = counts.map(|m| m.get(&c.id).copied().unwrap_or(0));
                channel_info(c, count)
            })
            .collect();
        self.channels.sort_by_key(|c| c.id);
        let chunks: Vec<IndexedChunk> = s
            .chunk_indexes
            .iter()
            .map(|c| IndexedChunk {
                span: ChunkSpan {
                    pos: c.chunk_start_offset,
                    length: c.chunk_length,
                    start: c.message_start_time,
                    end: c.message_end_time,
                },
                channels: c.message_index_offsets.keys().copied().collect(),
            })
            .collect();
        self.time_range = match &s.stats {
            Some(st) => Some((st.message_start_time, st.message_end_time)),
            None => span_range(chunks.iter().map(|c| c.span)),
        };
        self.mode = Mode::Indexed {
            chunks,
            merge: TimeMerge::new(Vec::new()),
        };
    }

    /// Lists channels and counts by reading the whole file once.
    fn scan(&mut self, why: &str) -> Result<(), IoError> {
        let mut stream = Linear::open(&self.src.path)?;
        let mut found: BTreeMap<u16, ChannelInfo> = BTreeMap::new();
        let mut range: Option<(u64, u64)> = None;
        while let Some(next) = stream.next() {
            match next {
                Ok(m) => {
                    let info = found
                        .entry(m.channel.id)
                        .or_insert_with(|| channel_info(&m.channel, Some(0)));
                    info.count = info.count.map(|n| n + 1);
                    let t = m.log_time;
                    range = Some(range.map_or((t, t), |(a, b)| (a.min(t), b.max(t))));
                }
                Err(e) => {
                    self.damage = Some(e);
                    break;
                }
            }
        }
        self.channels = found.into_values().collect();
        self.time_range = range;
        self.note = Some(format!("{why}; read in file order"));
        Ok(())
    }

    fn next_indexed(&mut self) -> Option<Result<StoredMessage, IoError>> {
        let Mode::Indexed { merge, .. } = &mut self.mode else {
            return None;
        };
        let src = &mut self.src;
        merge.next(|span, out| src.load(span, out))
    }

    fn next_linear(&mut self) -> Option<Result<StoredMessage, IoError>> {
        let Mode::Linear { stream: Some(s) } = &mut self.mode else {
            return None;
        };
        loop {
            match s.next()? {
                Ok(m) => {
                    let channel = u32::from(m.channel.id);
                    if self.src.wanted.contains(&channel) {
                        return Some(Ok(StoredMessage {
                            channel,
                            log_time: m.log_time,
                            data: m.data.into_owned(),
                        }));
                    }
                }
                Err(e) => return Some(Err(IoError::format(&self.src.path, e))),
            }
        }
    }
}

impl Source {
    /// The selected messages of the chunk at `span.pos` (`span.length` bytes, which must be in
    /// the file), CRC-checked.
    fn load(&mut self, span: &ChunkSpan, out: &mut Vec<StoredMessage>) -> Result<(), IoError> {
        let (pos, length) = (span.pos, span.length);
        let fail = |m: String| IoError::format(&self.path, format!("chunk at byte {pos}: {m}"));
        if length > self.len.saturating_sub(pos) || length > RECORD_LIMIT as u64 || length < 9 {
            return Err(fail(format!(
                "the index gives {length} bytes but the file has {} bytes from there",
                self.len.saturating_sub(pos)
            )));
        }
        let mut buf = vec![0u8; length as usize];
        self.file
            .seek(SeekFrom::Start(pos))
            .and_then(|_| self.file.read_exact(&mut buf))
            .map_err(|e| IoError::io(&self.path, e))?;
        // keylo decodes the chunk itself: the mcap readers size buffers from the declared
        // lengths (uncompressed size, record lengths) before the bytes exist.
        for (header, data) in chunk_messages(&buf).map_err(fail)? {
            let channel = u32::from(header.channel_id);
            if self.wanted.contains(&channel) {
                out.push(StoredMessage {
                    channel,
                    log_time: header.log_time,
                    data,
                });
            }
        }
        Ok(())
    }
}

fn span_range(spans: impl Iterator<Item = ChunkSpan>) -> Option<(u64, u64)> {
    spans.fold(None, |acc, s| match acc {
        None => Some((s.start, s.end)),
        Some((a, b)) => Some((a.min(s.start), b.max(s.end))),
    })
}

fn channel_info(c: &mcap::Channel, count: Option<u64>) -> ChannelInfo {
    ChannelInfo {
        id: u32::from(c.id),
        topic: c.topic.clone(),
        msg_type: c
            .schema
            .as_ref()
            .map(|s| s.name.clone())
            .unwrap_or_default(),
        encoding: Encoding::from_mcap(&c.message_encoding),
        encoding_name: c.message_encoding.clone(),
        count,
    }
}

impl MessageFile for McapFile {
    fn path(&self) -> &Path {
        &self.src.path
    }

    fn format(&self) -> BagFormat {
        BagFormat::Mcap
    }

    fn channels(&self) -> &[ChannelInfo] {
        &self.channels
    }

    fn time_range(&self) -> Option<(u64, u64)> {
        self.time_range
    }

    fn note(&self) -> Option<&str> {
        self.note.as_deref()
    }

    fn damage(&self) -> Option<&str> {
        self.damage.as_deref()
    }

    fn select(&mut self, channels: &[u32]) {
        self.src.wanted = channels.to_vec();
        match &mut self.mode {
            Mode::Indexed { chunks, merge } => {
                let spans = chunks
                    .iter()
                    .filter(|c| {
                        c.channels.is_empty()
                            || c.channels
                                .iter()
                                .any(|id| channels.contains(&u32::from(*id)))
                    })
                    .map(|c| c.span)
                    .collect();
                *merge = TimeMerge::new(spans);
                self.deferred = None;
            }
            // The stream reports its own damage when it reaches it.
            Mode::Linear { stream } => match Linear::open(&self.src.path) {
                Ok(s) => {
                    *stream = Some(Box::new(s));
                    self.deferred = None;
                }
                Err(e) => {
                    *stream = None;
                    self.deferred = Some(e.to_string());
                }
            },
        }
    }

    fn next_message(&mut self) -> Option<Result<StoredMessage, IoError>> {
        let next = match self.mode {
            Mode::Indexed { .. } => self.next_indexed(),
            Mode::Linear { .. } => self.next_linear(),
        };
        match next {
            Some(Err(e)) => {
                self.deferred = None;
                if let Mode::Linear { stream } = &mut self.mode {
                    *stream = None;
                }
                Some(Err(e))
            }
            Some(ok) => Some(ok),
            None => {
                let damage = self.deferred.take()?;
                Some(Err(IoError::format(&self.src.path, damage)))
            }
        }
    }
}

#[cfg(test)]
#[path = "mcap_tests.rs"]
mod tests;
