//! Log-time order over chunked files: chunks are loaded lazily, in order of their first
//! message time, and only while a chunk may hold a message earlier than every message already
//! loaded. Memory holds the chunks that overlap in time (one, for files written in order).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::file::StoredMessage;
use crate::IoError;

/// Where a chunk is and which times it covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ChunkSpan {
    /// File offset of the chunk record.
    pub pos: u64,
    /// Bytes of the chunk record, when the index says (0 when not).
    pub length: u64,
    /// First and last message time in the chunk, nanoseconds.
    pub start: u64,
    pub end: u64,
}

struct Pending {
    time: u64,
    seq: u64,
    msg: StoredMessage,
}

impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        (self.time, self.seq) == (other.time, other.seq)
    }
}
impl Eq for Pending {}
impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Pending {
    // Reversed: BinaryHeap is a max-heap and the earliest message comes first.
    fn cmp(&self, other: &Self) -> Ordering {
        (other.time, other.seq).cmp(&(self.time, self.seq))
    }
}

/// Merges the messages of a list of chunks into log-time order (ties: file order).
pub(crate) struct TimeMerge {
    chunks: Vec<ChunkSpan>,
    next_chunk: usize,
    heap: BinaryHeap<Pending>,
    seq: u64,
    /// A chunk that failed to load: reported once the messages before it are out.
    failed: Option<IoError>,
    done: bool,
}

impl TimeMerge {
    /// A merge over `chunks` (any order).
    pub fn new(mut chunks: Vec<ChunkSpan>) -> Self {
        chunks.sort_by_key(|c| (c.start, c.pos));
        Self {
            chunks,
            next_chunk: 0,
            heap: BinaryHeap::new(),
            seq: 0,
            failed: None,
            done: false,
        }
    }

    /// The next message; `load` appends the messages of one chunk to its buffer. After a
    /// failed chunk, the messages already loaded come out first, then the error, then `None`.
    pub fn next(
        &mut self,
        mut load: impl FnMut(&ChunkSpan, &mut Vec<StoredMessage>) -> Result<(), IoError>,
    ) -> Option<Result<StoredMessage, IoError>> {
        if self.done {
            return None;
        }
        let mut buf = Vec::new();
        while self.failed.is_none() {
            let Some(chunk) = self.chunks.get(self.next_chunk) else {
                break;
            };
            if self.heap.peek().is_some_and(|p| p.time < chunk.start) {
                break;
            }
            self.next_chunk += 1;
            buf.clear();
            match load(chunk, &mut buf) {
                Ok(()) => {
                    for msg in buf.drain(..) {
                        self.seq += 1;
                        let (time, seq) = (msg.log_time, self.seq);
                        self.heap.push(Pending { time, seq, msg });
                    }
                }
                Err(e) => self.failed = Some(e),
            }
        }
        if let Some(p) = self.heap.pop() {
            return Some(Ok(p.msg));
        }
        self.done = true;
        self.failed.take().map(Err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn msg(t: u64) -> StoredMessage {
        StoredMessage {
            channel: 0,
            log_time: t,
            data: vec![t as u8],
        }
    }

    fn span(pos: u64, start: u64, end: u64) -> ChunkSpan {
        ChunkSpan {
            pos,
            length: 0,
            start,
            end,
        }
    }

    #[test]
    fn overlapping_chunks_come_out_in_time_order_loading_lazily() {
        // Chunk at 100 holds 1, 5, 9; chunk at 200 holds 3, 4; chunk at 300 holds 20.
        let chunks = vec![span(300, 20, 20), span(100, 1, 9), span(200, 3, 4)];
        let mut merge = TimeMerge::new(chunks);
        let mut loaded = Vec::new();
        let mut out = Vec::new();
        while let Some(m) = merge.next(|c, buf| {
            loaded.push(c.pos);
            let times: &[u64] = match c.pos {
                100 => &[1, 5, 9],
                200 => &[3, 4],
                _ => &[20],
            };
            buf.extend(times.iter().map(|&t| msg(t)));
            Ok(())
        }) {
            out.push(m.unwrap().log_time);
            if out.len() == 1 {
                // The first message needed only the first chunk.
                assert_eq!(loaded, vec![100]);
            }
        }
        assert_eq!(out, vec![1, 3, 4, 5, 9, 20]);
        assert_eq!(loaded, vec![100, 200, 300]);
    }

    #[test]
    fn a_failed_chunk_comes_after_the_loaded_messages() {
        let mut merge = TimeMerge::new(vec![span(0, 1, 2), span(10, 3, 4)]);
        let mut results = Vec::new();
        while let Some(r) = merge.next(|c, buf| {
            if c.pos == 0 {
                buf.extend([msg(1), msg(2)]);
                Ok(())
            } else {
                Err(IoError::format(
                    std::path::Path::new("f"),
                    "chunk at byte 10: bad",
                ))
            }
        }) {
            results.push(r.map(|m| m.log_time).map_err(|e| e.to_string()));
        }
        assert_eq!(results.len(), 3);
        assert_eq!(results[0], Ok(1));
        assert_eq!(results[1], Ok(2));
        assert!(results[2].as_ref().unwrap_err().contains("byte 10"));
    }
}
