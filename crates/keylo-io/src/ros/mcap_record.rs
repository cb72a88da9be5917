//! MCAP records as keylo reads them: framed from the file with each declared length checked
//! against the bytes that are there before a buffer is allocated, and parsed by the `mcap`
//! crate only after the length-prefixed fields inside were checked the same way (its binrw
//! parser reserves a string's declared length, up to 4 GiB, before reading it).

use std::io::Read;

use mcap::records::{op, Record};

/// Bytes of a record's opcode and length.
pub(crate) const RECORD_HEADER: usize = 9;

/// Largest record or chunk read (compressed or not); a corrupt length beyond it is an error
/// instead of an allocation.
pub(crate) const RECORD_LIMIT: usize = 512 << 20;

/// A record's opcode, declared length and the bytes after its header (`None`: fewer than
/// [`RECORD_HEADER`] bytes).
pub(crate) fn split_record(bytes: &[u8]) -> Option<(u8, u64, &[u8])> {
    let (&opcode, rest) = bytes.split_first()?;
    let (len, rest) = rest.split_first_chunk::<8>()?;
    Some((opcode, u64::from_le_bytes(*len), rest))
}

/// Top-level records read from `reader`, which stands at byte `pos` of a section that ends at
/// byte `end` (the file, or the summary section).
pub(crate) struct FileRecords<R> {
    reader: R,
    pos: u64,
    end: u64,
    /// "file" or "summary section", for errors.
    what: &'static str,
}

impl<R: Read> FileRecords<R> {
    pub fn new(reader: R, pos: u64, end: u64, what: &'static str) -> Self {
        Self {
            reader,
            pos,
            end,
            what,
        }
    }

    /// The next byte to read.
    pub fn pos(&self) -> u64 {
        self.pos
    }

    /// Bytes from `pos` to the end of the section.
    pub fn left(&self) -> u64 {
        self.end.saturating_sub(self.pos)
    }

    /// Exactly `buf.len()` bytes, which the section must have.
    pub(crate) fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), String> {
        if (buf.len() as u64) > self.left() {
            return Err(format!(
                "the {} ends at byte {}, {} bytes short of what is read at byte {}",
                self.what,
                self.end,
                buf.len() as u64 - self.left(),
                self.pos
            ));
        }
        self.reader
            .read_exact(buf)
            .map_err(|e| format!("reading {} bytes at byte {}: {e}", buf.len(), self.pos))?;
        self.pos += buf.len() as u64;
        Ok(())
    }

    /// Reads the record at `pos`, its body into `body`, and returns its header (opcode and
    /// length); the declared length must fit in the section before anything is allocated.
    pub fn next(&mut self, body: &mut Vec<u8>) -> Result<[u8; RECORD_HEADER], String> {
        let at = self.pos;
        let left = self.left();
        if left == 0 {
            return Err(format!(
                "the {} ends at byte {}, before its footer (cut short?)",
                self.what, self.end
            ));
        }
        if left < RECORD_HEADER as u64 {
            return Err(format!(
                "the {} ends at byte {} with {left} bytes of a record header at byte {at} \
                 (cut short?)",
                self.what, self.end
            ));
        }
        let mut head = [0u8; RECORD_HEADER];
        self.read_exact(&mut head)?;
        let Some((opcode, len, _)) = split_record(&head) else {
            return Err(format!("record header at byte {at} unreadable"));
        };
        let room = left - RECORD_HEADER as u64;
        if len > room || len > RECORD_LIMIT as u64 {
            let why = if len > room {
                format!("the {} has {room} bytes after its header", self.what)
            } else {
                format!("over the {} MiB record limit", RECORD_LIMIT >> 20)
            };
            return Err(format!(
                "record at byte {at} (opcode {opcode:#04x}) declares {len} bytes, but {why}"
            ));
        }
        body.clear();
        body.resize(len as usize, 0);
        self.read_exact(body)?;
        Ok(head)
    }
}

/// One field of a record body, in the order of the MCAP specification, up to the last
/// length-prefixed one.
#[derive(Clone, Copy)]
enum Field {
    Fixed(usize),
    /// A u32 byte length and that many bytes (a string, or a map of integers).
    Prefixed(&'static str),
    /// A u32 byte length, then strings (keys and values).
    StringMap(&'static str),
}

fn layout(opcode: u8) -> &'static [Field] {
    use Field::*;
    match opcode {
        op::SCHEMA => &[Fixed(2), Prefixed("name"), Prefixed("encoding")],
        op::CHANNEL => &[
            Fixed(4),
            Prefixed("topic"),
            Prefixed("message_encoding"),
            StringMap("metadata"),
        ],
        op::CHUNK => &[Fixed(28), Prefixed("compression")],
        op::CHUNK_INDEX => &[
            Fixed(32),
            Prefixed("message_index_offsets"),
            Fixed(8),
            Prefixed("compression"),
        ],
        _ => &[],
    }
}

/// `mcap::parse_record`, after checking that the length-prefixed fields of the record types
/// keylo parses fit in `body`.
pub(crate) fn parse(opcode: u8, body: &[u8]) -> Result<Record<'_>, String> {
    let mut at = 0;
    for field in layout(opcode) {
        match *field {
            Field::Fixed(n) => at += n,
            Field::Prefixed(name) => at = prefixed_end(body, at, name)?,
            Field::StringMap(name) => {
                let end = prefixed_end(body, at, name)?;
                let mut entry = at + 4;
                while entry < end {
                    entry = prefixed_end(&body[..end], entry, name)?;
                }
                at = end;
            }
        }
    }
    mcap::parse_record(opcode, body).map_err(|e| e.to_string())
}

/// The end of the length-prefixed field `name` at byte `at` of `body`.
fn prefixed_end(body: &[u8], at: usize, name: &str) -> Result<usize, String> {
    let Some(len) = body.get(at..).and_then(|b| b.first_chunk::<4>()) else {
        return Err(format!(
            "the record ends at byte {} before the length of `{name}` (byte {at})",
            body.len()
        ));
    };
    let len = u32::from_le_bytes(*len);
    let start = at + 4;
    match usize::try_from(len).ok().and_then(|n| start.checked_add(n)) {
        Some(end) if end <= body.len() => Ok(end),
        _ => Err(format!(
            "`{name}` (byte {at} of the record) declares {len} bytes, but {} follow",
            body.len() - start
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn string(s: &str, claim: Option<u32>) -> Vec<u8> {
        let mut out = claim.unwrap_or(s.len() as u32).to_le_bytes().to_vec();
        out.extend(s.as_bytes());
        out
    }

    /// A channel record body whose metadata map holds `key` = "v".
    fn channel(key_claim: Option<u32>) -> Vec<u8> {
        let entry = [string("key", key_claim), string("v", None)].concat();
        let mut body = [7u16.to_le_bytes(), 0u16.to_le_bytes()].concat();
        body.extend(string("/t", None));
        body.extend(string("cdr", None));
        body.extend((entry.len() as u32).to_le_bytes());
        body.extend(entry);
        body
    }

    #[test]
    fn lengths_inside_records_are_checked_before_parsing() {
        match parse(op::CHANNEL, &channel(None)) {
            Ok(Record::Channel(c)) => assert_eq!((c.id, c.metadata["key"].as_str()), (7, "v")),
            other => panic!("{other:?}"),
        }
        let e = parse(op::CHANNEL, &channel(Some(u32::MAX))).unwrap_err();
        assert!(e.contains("`metadata`") && e.contains("4294967295"), "{e}");
        let e = parse(op::CHANNEL, &channel(None)[..10]).unwrap_err();
        assert!(e.contains("before the length of `message_encoding`"), "{e}");
    }
}
