//! The two wire formats of ROS messages: ROS1 serialisation (little-endian, packed) and the
//! CDR of ROS2 (4-byte encapsulation header, then every primitive aligned to its size relative
//! to the end of that header, byte order from the header).
//!
//! Why not a CDR crate: `cdr-encoding` (serde) decodes the CDR half, but bags and mcap channels
//! with `message_encoding = "ros1"` need the ROS1 layout too, and keylo reads exactly three
//! message types (PointCloud2, Image, String). One cursor with an alignment switch covers
//! both formats, borrows the point data instead of copying it, and reports the byte offset and
//! field of any truncation.

/// How a message payload is serialised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// ROS1 serialisation (bags, and mcap channels with `message_encoding = "ros1"`).
    Ros1,
    /// OMG CDR as ROS2 writes it (`message_encoding = "cdr"`).
    Cdr,
}

impl Encoding {
    /// The encoding of an mcap channel's `message_encoding`, if keylo reads it.
    pub fn from_mcap(name: &str) -> Option<Self> {
        match name {
            "ros1" => Some(Self::Ros1),
            "cdr" => Some(Self::Cdr),
            _ => None,
        }
    }

    /// The name used in files (`ros1` or `cdr`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Ros1 => "ros1",
            Self::Cdr => "cdr",
        }
    }
}

/// A cursor over one serialised message.
pub(crate) struct WireReader<'a> {
    buf: &'a [u8],
    pos: usize,
    /// Where alignment is counted from (after the CDR encapsulation header).
    origin: usize,
    /// Largest alignment applied (0: none, ROS1).
    max_align: usize,
    big_endian: bool,
}

impl<'a> WireReader<'a> {
    /// A reader of `buf`; for CDR the encapsulation header is read and checked.
    pub(crate) fn new(buf: &'a [u8], encoding: Encoding) -> Result<Self, String> {
        let mut r = Self {
            buf,
            pos: 0,
            origin: 0,
            max_align: 0,
            big_endian: false,
        };
        if encoding == Encoding::Cdr {
            let head = r.take(4, "CDR encapsulation header")?;
            // Plain CDR (XCDR1) and XCDR2 for final types; ROS2 messages are final.
            (r.big_endian, r.max_align) = match (head[0], head[1]) {
                (0, 0x00) => (true, 8),
                (0, 0x01) => (false, 8),
                (0, 0x06) => (true, 4),
                (0, 0x07) => (false, 4),
                (a, b) => {
                    return Err(format!(
                        "CDR encapsulation kind 0x{a:02x}{b:02x} is not supported \
                         (expected 0x0000/0x0001 plain CDR or 0x0006/0x0007 XCDR2)"
                    ))
                }
            };
            r.origin = 4;
        }
        Ok(r)
    }

    /// Byte offset of the cursor in the message.
    #[cfg(test)]
    pub fn pos(&self) -> usize {
        self.pos
    }

    fn align(&mut self, size: usize) {
        let a = size.min(self.max_align);
        if a > 1 {
            let rel = self.pos - self.origin;
            self.pos += (a - rel % a) % a;
        }
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.buf.len());
        match end {
            Some(end) => {
                let s = &self.buf[self.pos..end];
                self.pos = end;
                Ok(s)
            }
            None => Err(format!(
                "`{what}` at byte {}: the message ends there (needs {n} bytes, {} left)",
                self.pos,
                self.buf.len().saturating_sub(self.pos)
            )),
        }
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        self.align(N);
        let mut out = [0u8; N];
        out.copy_from_slice(self.take(N, what)?);
        Ok(out)
    }

    /// A `uint8` (also `bool` and `char`).
    pub(crate) fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.array::<1>(what)?[0])
    }

    /// A `uint32`.
    pub(crate) fn u32(&mut self, what: &str) -> Result<u32, String> {
        let b = self.array::<4>(what)?;
        Ok(if self.big_endian {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        })
    }

    /// An `int32`.
    pub(crate) fn i32(&mut self, what: &str) -> Result<i32, String> {
        Ok(self.u32(what)? as i32)
    }

    /// A sequence or string length, checked against the bytes left (each element at least
    /// `min_elem` bytes) so a corrupt length never allocates.
    pub(crate) fn seq_len(&mut self, what: &str, min_elem: usize) -> Result<usize, String> {
        let at = self.pos;
        let n = self.u32(what)? as usize;
        let left = self.buf.len().saturating_sub(self.pos);
        if n.saturating_mul(min_elem) > left {
            return Err(format!(
                "`{what}` at byte {at}: length {n} but only {left} bytes follow"
            ));
        }
        Ok(n)
    }

    /// A `string` (UTF-8; CDR's terminating NUL is dropped).
    pub(crate) fn string(&mut self, what: &str) -> Result<&'a str, String> {
        let n = self.seq_len(what, 1)?;
        let at = self.pos;
        let mut bytes = self.take(n, what)?;
        if self.max_align > 0 {
            bytes = bytes.strip_suffix(&[0]).unwrap_or(bytes);
        }
        std::str::from_utf8(bytes).map_err(|e| format!("`{what}` at byte {at}: not UTF-8 ({e})"))
    }

    /// A `uint8[]`, borrowed.
    pub(crate) fn bytes(&mut self, what: &str) -> Result<&'a [u8], String> {
        let n = self.seq_len(what, 1)?;
        self.take(n, what)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdr_aligns_after_the_header_and_strips_nul() {
        // header LE, u8 7, pad to 4, u32 5, string "ab\0", pad, bytes [1, 2]
        let buf = [
            0, 1, 0, 0, 7, 0, 0, 0, 5, 0, 0, 0, 3, 0, 0, 0, b'a', b'b', 0, 0, 2, 0, 0, 0, 1, 2,
        ];
        let mut r = WireReader::new(&buf, Encoding::Cdr).unwrap();
        assert_eq!(r.u8("a").unwrap(), 7);
        assert_eq!(r.u32("b").unwrap(), 5);
        assert_eq!(r.string("s").unwrap(), "ab");
        assert_eq!(r.bytes("d").unwrap(), &[1, 2]);
        assert_eq!(r.pos(), buf.len());
    }

    #[test]
    fn big_endian_cdr_and_packed_ros1() {
        let mut r = WireReader::new(&[0, 0, 0, 0, 0, 0, 1, 2], Encoding::Cdr).unwrap();
        assert_eq!(r.u32("x").unwrap(), 0x0102);
        let mut r = WireReader::new(&[9, 2, 0, 0, 0], Encoding::Ros1).unwrap();
        assert_eq!(r.u8("a").unwrap(), 9);
        assert_eq!(r.u32("b").unwrap(), 2); // no padding in ROS1
    }

    #[test]
    fn truncation_and_bad_lengths_name_field_and_offset() {
        let mut r = WireReader::new(&[1, 0], Encoding::Ros1).unwrap();
        let e = r.u32("height").unwrap_err();
        assert!(
            e.contains("`height` at byte 0") && e.contains("2 left"),
            "{e}"
        );
        let mut r = WireReader::new(&[0xff, 0xff, 0xff, 0x7f, 1], Encoding::Ros1).unwrap();
        let e = r.bytes("data").unwrap_err();
        assert!(e.contains("length 2147483647"), "{e}");
        let e = WireReader::new(&[0, 3, 0, 0], Encoding::Cdr).err().unwrap();
        assert!(e.contains("0x0003"), "{e}");
        assert!(WireReader::new(&[0], Encoding::Cdr).is_err());
    }
}
