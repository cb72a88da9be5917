//! The streaming pieces of MCAP reading: the summary through the sans-io reader, and
//! messages in file order for files without a usable summary.
//!
//! In file order keylo frames the top-level records itself: a record's declared length is
//! checked against the bytes the file has left before its buffer is allocated, and chunks are
//! decoded by [`super::mcap_chunk`], so a corrupt length is an error naming the record, never an
//! allocation of that length.

use std::borrow::Cow;
use std::collections::VecDeque;
use std::fs::File;
use std::io::{BufReader, Read, Seek};
use std::path::Path;

use mcap::read::ChannelAccumulator;
use mcap::records::{op, Record};
use mcap::sans_io::{SummaryReadEvent, SummaryReader, SummaryReaderOptions};
use mcap::{Message, Summary, MAGIC};

use super::mcap_chunk::{chunk_content, records, split_record, RECORD_HEADER};
use crate::IoError;

/// Largest record or chunk read (compressed or not); a corrupt length beyond it is an error
/// instead of an allocation.
pub(crate) const RECORD_LIMIT: usize = 512 << 20;

/// The summary section through the sans-io reader (reads clamped to the file size; every
/// record length is bounded by the bytes from the summary's start to the end of the file).
pub(crate) fn read_summary(
    file: &mut BufReader<File>,
    len: u64,
) -> Result<Option<Summary>, String> {
    let options = SummaryReaderOptions::default()
        .with_file_size(len)
        .with_record_length_limit(RECORD_LIMIT);
    let mut reader = SummaryReader::new_with_options(options);
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| e.to_string())? {
            SummaryReadEvent::ReadRequest(need) => {
                let n = file.read(reader.insert(need)).map_err(|e| e.to_string())?;
                reader.notify_read(n);
            }
            SummaryReadEvent::SeekRequest(to) => {
                let at = file.seek(to).map_err(|e| e.to_string())?;
                reader.notify_seeked(at);
            }
        }
    }
    Ok(reader.finish())
}

/// The part of the file the stream is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Part {
    StartMagic,
    /// Records up to the data end record, under the data section CRC.
    Data,
    /// Summary records: skipped (their lengths still checked) up to the footer.
    Summary,
    EndMagic,
    Done,
}

/// Messages in file order, chunk CRCs checked before a chunk's messages come out.
pub(crate) struct Linear {
    file: BufReader<File>,
    len: u64,
    /// The next byte to read.
    pos: u64,
    part: Part,
    data_crc: crc32fast::Hasher,
    channels: ChannelAccumulator<'static>,
    /// Messages of the last chunk not handed out yet.
    pending: VecDeque<Message<'static>>,
    /// The error of a record inside that chunk, once `pending` is out.
    failed: Option<String>,
    /// The body of the record being read (reused).
    body: Vec<u8>,
    index: u64,
}

impl Linear {
    pub fn open(path: &Path) -> Result<Self, IoError> {
        let file = File::open(path).map_err(|e| IoError::io(path, e))?;
        let len = file.metadata().map_err(|e| IoError::io(path, e))?.len();
        Ok(Self {
            file: BufReader::new(file),
            len,
            pos: 0,
            part: Part::StartMagic,
            data_crc: crc32fast::Hasher::new(),
            channels: ChannelAccumulator::default(),
            pending: VecDeque::new(),
            failed: None,
            body: Vec::new(),
            index: 0,
        })
    }

    /// The next message; the error says after which message and near which byte.
    pub fn next(&mut self) -> Option<Result<Message<'static>, String>> {
        match self.advance() {
            Ok(Some(m)) => {
                self.index += 1;
                Some(Ok(m))
            }
            Ok(None) => None,
            Err(e) => {
                self.part = Part::Done;
                self.pending.clear();
                Some(Err(format!(
                    "{e} (reading near byte {}, after message {} of the file; \
                     the messages before it were read)",
                    self.pos, self.index,
                )))
            }
        }
    }

    fn advance(&mut self) -> Result<Option<Message<'static>>, String> {
        loop {
            if let Some(m) = self.pending.pop_front() {
                return Ok(Some(m));
            }
            if let Some(e) = self.failed.take() {
                return Err(e);
            }
            match self.part {
                Part::Done => return Ok(None),
                Part::StartMagic => {
                    self.magic("start")?;
                    self.part = Part::Data;
                }
                Part::EndMagic => {
                    self.magic("end")?;
                    self.part = Part::Done;
                }
                Part::Data | Part::Summary => {
                    let at = self.pos;
                    let opcode = self.read_record()?;
                    let body = std::mem::take(&mut self.body);
                    let message = self.record(at, opcode, &body);
                    self.body = body;
                    if let Some(m) = message? {
                        return Ok(Some(m));
                    }
                }
            }
        }
    }

    fn magic(&mut self, which: &str) -> Result<(), String> {
        let at = self.pos;
        if self.len.saturating_sub(at) < MAGIC.len() as u64 {
            return Err(format!(
                "the file ends at byte {} where its {which} magic (8 bytes) should be",
                self.len
            ));
        }
        let mut magic = [0u8; 8];
        self.read(&mut magic)?;
        if magic != MAGIC {
            return Err(format!("no MCAP {which} magic at byte {at}"));
        }
        if self.part == Part::StartMagic {
            self.data_crc.update(&magic);
        }
        Ok(())
    }

    /// Reads the record at `pos` (its body into `self.body`) and returns its opcode; its
    /// declared length must fit in the bytes the file has left.
    fn read_record(&mut self) -> Result<u8, String> {
        let at = self.pos;
        let left = self.len.saturating_sub(at);
        if left < RECORD_HEADER as u64 {
            return Err(format!(
                "the file ends at byte {} before its footer ({left} bytes of a record header \
                 at byte {at}; cut short?)",
                self.len
            ));
        }
        let mut head = [0u8; RECORD_HEADER];
        self.read(&mut head)?;
        let Some((opcode, len, _)) = split_record(&head) else {
            return Err(format!("record header at byte {at} unreadable"));
        };
        let room = left - RECORD_HEADER as u64;
        if len > room || len > RECORD_LIMIT as u64 {
            let why = if len > room {
                format!("the file has {room} bytes after its header")
            } else {
                format!("over the {} MiB record limit", RECORD_LIMIT >> 20)
            };
            return Err(format!(
                "record at byte {at} (opcode {opcode:#04x}) declares {len} bytes, but {why}"
            ));
        }
        let mut body = std::mem::take(&mut self.body);
        body.clear();
        body.resize(len as usize, 0);
        let read = self.read(&mut body);
        if self.part == Part::Data && opcode != op::DATA_END {
            self.data_crc.update(&head);
            self.data_crc.update(&body);
        }
        self.body = body;
        read.map(|()| opcode)
    }

    /// Exactly `buf.len()` bytes at `pos` (the caller has checked that the file has them).
    fn read(&mut self, buf: &mut [u8]) -> Result<(), String> {
        self.file
            .read_exact(buf)
            .map_err(|e| format!("reading {} bytes at byte {}: {e}", buf.len(), self.pos))?;
        self.pos += buf.len() as u64;
        Ok(())
    }

    /// Acts on one top-level record (at byte `at`); a message comes back.
    fn record(
        &mut self,
        at: u64,
        opcode: u8,
        body: &[u8],
    ) -> Result<Option<Message<'static>>, String> {
        match (opcode, self.part) {
            (op::FOOTER, _) => {
                mcap::parse_record(opcode, body)
                    .map_err(|e| format!("footer at byte {at}: {e}"))?;
                self.part = Part::EndMagic;
            }
            (op::DATA_END, Part::Data) => {
                let saved = match mcap::parse_record(opcode, body) {
                    Ok(Record::DataEnd(d)) => d.data_section_crc,
                    Ok(_) => 0,
                    Err(e) => return Err(format!("data end record at byte {at}: {e}")),
                };
                let calculated = std::mem::take(&mut self.data_crc).finalize();
                if saved != 0 && saved != calculated {
                    return Err(format!(
                        "data section CRC mismatch: the bytes before byte {at} hash to \
                         {calculated:08X}, the data end record says {saved:08X}"
                    ));
                }
                self.part = Part::Summary;
            }
            (op::CHUNK, Part::Data) => self.chunk(at, body)?,
            (_, Part::Data) => {
                return self
                    .link(opcode, body)
                    .map_err(|e| format!("record at byte {at} (opcode {opcode:#04x}): {e}"));
            }
            _ => {}
        }
        Ok(None)
    }

    /// Queues the messages of the chunk record at byte `at`, whose CRC is checked first; a bad
    /// record inside is reported after the messages before it.
    fn chunk(&mut self, at: u64, body: &[u8]) -> Result<(), String> {
        let fail = |e: String| format!("chunk at byte {at}: {e}");
        let content = chunk_content(body).map_err(fail)?;
        for record in records(&content) {
            let linked = record.map_err(fail).and_then(|(offset, opcode, body)| {
                self.link(opcode, body)
                    .map_err(|e| fail(format!("record at byte {offset} of its records: {e}")))
            });
            match linked {
                Ok(Some(m)) => self.pending.push_back(m),
                Ok(None) => {}
                Err(e) => {
                    self.failed = Some(e);
                    break;
                }
            }
        }
        Ok(())
    }

    /// Remembers schemas and channels; a message comes back linked to its channel.
    fn link(&mut self, opcode: u8, body: &[u8]) -> Result<Option<Message<'static>>, String> {
        if !matches!(opcode, op::SCHEMA | op::CHANNEL | op::MESSAGE) {
            return Ok(None);
        }
        let record = mcap::parse_record(opcode, body).map_err(|e| e.to_string())?;
        let linked = match record {
            Record::Schema { header, data } => self.channels.add_schema_from_slice(header, &data),
            Record::Channel(channel) => self.channels.add_channel(channel),
            Record::Message { header, data } => {
                let channel = self.channels.get(header.channel_id).ok_or_else(|| {
                    format!(
                        "message {} on channel {}, which no channel record before it defines",
                        header.sequence, header.channel_id
                    )
                })?;
                return Ok(Some(Message {
                    channel,
                    sequence: header.sequence,
                    log_time: header.log_time,
                    publish_time: header.publish_time,
                    data: Cow::Owned(data.into_owned()),
                }));
            }
            _ => Ok(()),
        };
        linked.map(|()| None).map_err(|e| e.to_string())
    }
}
