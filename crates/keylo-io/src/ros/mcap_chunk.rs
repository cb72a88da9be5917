//! MCAP chunks decoded by keylo itself, so that no buffer is larger than the input can fill:
//! the compressed bytes are the chunk record the caller read (bounded by the file), the
//! decompressed bytes grow only as the decompressor produces them (never past the size the
//! header declares, nor [`RECORD_LIMIT`]), and each record inside is bounded by the bytes the
//! chunk actually holds. (The `mcap` crate's readers size their buffers from the declared
//! lengths before any byte arrives.)

use std::borrow::Cow;
use std::io::Read;

use mcap::records::{op, ChunkHeader, MessageHeader, Record};

use super::mcap_record::{parse, split_record, RECORD_HEADER, RECORD_LIMIT};

/// The first buffer for a compressed chunk, as a multiple of its compressed size (a guess, not a
/// limit): past it the buffer grows only as decompressed bytes arrive.
const FIRST_GUESS_RATIO: usize = 4;

/// The records field of a chunk (`body`: the chunk record after opcode and length),
/// decompressed and checked against the header's size and CRC.
pub(crate) fn chunk_content(body: &[u8]) -> Result<Cow<'_, [u8]>, String> {
    let (header, data) = match parse(op::CHUNK, body)? {
        Record::Chunk { header, data } => (header, data),
        _ => return Err("not a chunk record".into()),
    };
    let content = if header.compression.is_empty() {
        data
    } else {
        Cow::Owned(decompress(&header, &data)?)
    };
    let saved = header.uncompressed_crc;
    if saved != 0 {
        let calculated = crc32fast::hash(&content);
        if calculated != saved {
            return Err(format!(
                "chunk CRC mismatch: its records hash to {calculated:08X}, the header says \
                 {saved:08X}"
            ));
        }
    }
    Ok(content)
}

/// The decompressed records of a chunk, exactly `header.uncompressed_size` bytes.
fn decompress(header: &ChunkHeader, data: &[u8]) -> Result<Vec<u8>, String> {
    let declared = header.uncompressed_size;
    let size = usize::try_from(declared)
        .ok()
        .filter(|&n| n <= RECORD_LIMIT)
        .ok_or_else(|| {
            format!(
                "the header declares {declared} uncompressed bytes, over the {} MiB limit",
                RECORD_LIMIT >> 20
            )
        })?;
    let mut out = Vec::with_capacity(size.min(data.len().saturating_mul(FIRST_GUESS_RATIO)));
    let name = header.compression.as_str();
    let read = match name {
        "zstd" => zstd::stream::read::Decoder::with_buffer(data)
            .and_then(|d| d.take(declared).read_to_end(&mut out)),
        "lz4" => lz4::Decoder::new(data).and_then(|d| d.take(declared).read_to_end(&mut out)),
        other => return Err(format!("unsupported chunk compression `{other}`")),
    };
    read.map_err(|e| format!("{name} decompression failed after {} bytes: {e}", out.len()))?;
    if out.len() != size {
        return Err(format!(
            "{name} data decompressed to {} bytes but the chunk header declares {size}",
            out.len()
        ));
    }
    Ok(out)
}

/// The records in a chunk's decompressed `content`, each as (offset in `content`, opcode,
/// body); the first record whose length runs past the end is an error, and the last item.
pub(crate) fn records(content: &[u8]) -> impl Iterator<Item = Result<(usize, u8, &[u8]), String>> {
    let mut at = 0;
    let mut failed = false;
    std::iter::from_fn(move || {
        if failed || at >= content.len() {
            return None;
        }
        let record = record_at(content, at);
        match &record {
            Ok((_, _, body)) => at += RECORD_HEADER + body.len(),
            Err(_) => failed = true,
        }
        Some(record)
    })
}

fn record_at(content: &[u8], at: usize) -> Result<(usize, u8, &[u8]), String> {
    let rest = content.get(at..).unwrap_or_default();
    let Some((opcode, len, body)) = split_record(rest) else {
        return Err(format!(
            "record at byte {at} of the chunk's records: {} bytes left, less than a record \
             header ({RECORD_HEADER})",
            rest.len()
        ));
    };
    match usize::try_from(len).ok().and_then(|n| body.get(..n)) {
        Some(body) => Ok((at, opcode, body)),
        None => Err(format!(
            "record at byte {at} of the chunk's records (opcode {opcode:#04x}) declares {len} \
             bytes but the chunk has {} bytes after its header",
            body.len()
        )),
    }
}

/// The messages of a chunk record (`record`: opcode, length, body, as the chunk index gives
/// it), CRC-checked before any message comes out.
pub(crate) fn chunk_messages(record: &[u8]) -> Result<Vec<(MessageHeader, Vec<u8>)>, String> {
    let (opcode, len, rest) = split_record(record).ok_or("shorter than a record header")?;
    if opcode != op::CHUNK {
        return Err(format!(
            "expected a chunk record (opcode 0x06), found {opcode:#04x}"
        ));
    }
    let body = usize::try_from(len)
        .ok()
        .and_then(|n| rest.get(..n))
        .ok_or_else(|| {
            format!(
                "the chunk record declares {len} bytes but the index gives it {} after its header",
                rest.len()
            )
        })?;
    let content = chunk_content(body)?;
    let mut out = Vec::new();
    for record in records(&content) {
        let (at, opcode, body) = record?;
        if opcode != op::MESSAGE {
            continue;
        }
        match parse(opcode, body) {
            Ok(Record::Message { header, data }) => out.push((header, data.into_owned())),
            Ok(_) => {
                return Err(format!(
                    "record at byte {at} of the chunk's records: not a message"
                ))
            }
            Err(e) => return Err(format!("message at byte {at} of the chunk's records: {e}")),
        }
    }
    Ok(out)
}
