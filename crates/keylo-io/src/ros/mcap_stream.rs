//! Messages of an MCAP file in file order, for files without a usable summary. Records are
//! framed by [`FileRecords`] (each length checked against the bytes the file has left before
//! its buffer is allocated) and chunks decoded by [`super::mcap_chunk`], so a corrupt length
//! is an error naming the record, never an allocation of that length.

use std::borrow::Cow;
use std::collections::VecDeque;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use mcap::read::ChannelAccumulator;
use mcap::records::{op, Record};
use mcap::{Message, MAGIC};

use super::mcap_chunk::{chunk_content, records};
use super::mcap_record::{parse, FileRecords};
use crate::IoError;

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
    file: FileRecords<BufReader<File>>,
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
            file: FileRecords::new(BufReader::new(file), 0, len, "file"),
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
    pub(crate) fn next(&mut self) -> Option<Result<Message<'static>, String>> {
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
                    self.file.pos(),
                    self.index,
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
                    let at = self.file.pos();
                    let mut body = std::mem::take(&mut self.body);
                    let message = self.record(at, &mut body);
                    self.body = body;
                    if let Some(m) = message? {
                        return Ok(Some(m));
                    }
                }
            }
        }
    }

    fn magic(&mut self, which: &str) -> Result<(), String> {
        let at = self.file.pos();
        let mut magic = [0u8; 8];
        self.file
            .read_exact(&mut magic)
            .map_err(|e| format!("no MCAP {which} magic: {e}"))?;
        if magic != MAGIC {
            return Err(format!("no MCAP {which} magic at byte {at}"));
        }
        if self.part == Part::StartMagic {
            self.data_crc.update(&magic);
        }
        Ok(())
    }

    /// Reads and acts on the record at byte `at` (its body into `body`); a message comes back.
    fn record(&mut self, at: u64, body: &mut Vec<u8>) -> Result<Option<Message<'static>>, String> {
        let head = self.file.next(body)?;
        let opcode = head[0];
        if self.part == Part::Data && opcode != op::DATA_END {
            self.data_crc.update(&head);
            self.data_crc.update(body);
        }
        match (opcode, self.part) {
            (op::FOOTER, _) => {
                parse(opcode, body).map_err(|e| format!("footer at byte {at}: {e}"))?;
                self.part = Part::EndMagic;
            }
            (op::DATA_END, Part::Data) => {
                let saved = match parse(opcode, body) {
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
        let linked = match parse(opcode, body)? {
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
