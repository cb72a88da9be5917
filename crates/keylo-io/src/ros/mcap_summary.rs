//! The summary section of an MCAP file (schemas, channels, statistics, chunk indexes), found
//! through the footer at the end of the file. Its records are framed and checked like every
//! other ([`super::mcap_record`]), so a corrupt length is an error, not an allocation.

use std::fs::File;
use std::io::{BufReader, Seek, SeekFrom};
use std::sync::Arc;

use mcap::read::ChannelAccumulator;
use mcap::records::{op, ChunkIndex, Record, Statistics};
use mcap::{Channel, MAGIC};

use super::mcap_record::{parse, split_record, FileRecords, RECORD_HEADER};

/// What keylo uses of a summary.
pub(crate) struct McapSummary {
    /// Channels, linked to their schemas, by id.
    pub channels: Vec<Arc<Channel<'static>>>,
    pub stats: Option<Statistics>,
    pub chunk_indexes: Vec<ChunkIndex>,
}

/// The footer record (opcode, length, a 20-byte body) and the end magic.
const FOOTER_AND_MAGIC: u64 = RECORD_HEADER as u64 + 20 + 8;

/// The summary of the file (`len` bytes), `None` when its footer says it has none.
pub(crate) fn read_summary(
    file: &mut BufReader<File>,
    len: u64,
) -> Result<Option<McapSummary>, String> {
    let Some(footer_at) = len.checked_sub(MAGIC.len() as u64 + FOOTER_AND_MAGIC) else {
        return Err(format!(
            "{len} bytes, too few for the start magic, a footer and the end magic"
        ));
    };
    let footer_at = footer_at + MAGIC.len() as u64;
    file.seek(SeekFrom::Start(footer_at))
        .map_err(|e| e.to_string())?;
    let mut tail = [0u8; FOOTER_AND_MAGIC as usize];
    let mut records = FileRecords::new(&mut *file, footer_at, len, "file");
    records.read_exact(&mut tail)?;
    let (footer, magic) = tail.split_at(tail.len() - MAGIC.len());
    if magic != MAGIC {
        return Err("no end magic in the last 8 bytes (cut short?)".into());
    }
    let summary_start = match split_record(footer) {
        Some((op::FOOTER, _, body)) => body.first_chunk::<8>().map(|b| u64::from_le_bytes(*b)),
        _ => None,
    };
    let Some(summary_start) = summary_start else {
        return Err(format!("no footer record at byte {footer_at}"));
    };
    if summary_start == 0 {
        return Ok(None);
    }
    if !(MAGIC.len() as u64..=footer_at).contains(&summary_start) {
        return Err(format!(
            "the footer puts the summary at byte {summary_start}, outside the records \
             (bytes {}..{footer_at})",
            MAGIC.len()
        ));
    }
    file.seek(SeekFrom::Start(summary_start))
        .map_err(|e| e.to_string())?;
    let records = FileRecords::new(file, summary_start, footer_at, "summary section");
    summary_records(records).map(Some)
}

/// Reads the summary section's records up to the footer.
fn summary_records(mut records: FileRecords<&mut BufReader<File>>) -> Result<McapSummary, String> {
    let mut linked = ChannelAccumulator::default();
    let mut ids = Vec::new();
    let mut summary = McapSummary {
        channels: Vec::new(),
        stats: None,
        chunk_indexes: Vec::new(),
    };
    let mut body = Vec::new();
    while records.left() > 0 {
        let at = records.pos();
        let opcode = records.next(&mut body)?[0];
        if !matches!(
            opcode,
            op::SCHEMA | op::CHANNEL | op::CHUNK_INDEX | op::STATISTICS
        ) {
            continue;
        }
        let fail = |e: String| format!("summary record at byte {at} (opcode {opcode:#04x}): {e}");
        let done = match parse(opcode, &body).map_err(fail)? {
            Record::Schema { header, data } => linked.add_schema_from_slice(header, &data),
            Record::Channel(channel) => {
                ids.push(channel.id);
                linked.add_channel(channel)
            }
            Record::ChunkIndex(index) => {
                summary.chunk_indexes.push(index);
                Ok(())
            }
            Record::Statistics(stats) => {
                summary.stats = Some(stats);
                Ok(())
            }
            _ => Ok(()),
        };
        done.map_err(|e| fail(e.to_string()))?;
    }
    ids.sort_unstable();
    ids.dedup();
    summary.channels = ids.into_iter().filter_map(|id| linked.get(id)).collect();
    Ok(summary)
}
