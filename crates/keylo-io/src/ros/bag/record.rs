//! ROS1 bag records (format 2.0): `header_len u32, header, data_len u32, data`, the header a
//! list of `len u32, "name=value"` fields with the record type in field `op`; and the chunk
//! codecs (`none`, `bz2`, `lz4`).

use std::io::Read;

// The largest chunk keylo decompresses, as for mcap records (a real bag's chunks are about
// 768 KiB, or one message when it is larger).
use crate::ros::mcap_record::RECORD_LIMIT;

/// Record types (`op`).
pub(crate) mod op {
    pub const MSG_DATA: u8 = 0x02;
    pub const BAG_HEADER: u8 = 0x03;
    pub const CHUNK: u8 = 0x05;
    pub const CHUNK_INFO: u8 = 0x06;
    pub const CONNECTION: u8 = 0x07;
}

/// The fields of a record header (or of a connection record's data).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Fields<'a>(Vec<(&'a [u8], &'a [u8])>);

impl<'a> Fields<'a> {
    /// Parses `len u32, name=value` fields.
    pub(crate) fn parse(mut buf: &'a [u8]) -> Result<Self, String> {
        let mut out = Vec::new();
        while !buf.is_empty() {
            let len = le_u32(buf).ok_or("header field length cut short")? as usize;
            let field = buf
                .get(4..4 + len)
                .ok_or_else(|| format!("header field of {len} bytes runs past the header"))?;
            let eq = field
                .iter()
                .position(|&b| b == b'=')
                .ok_or("header field without `=`")?;
            out.push((&field[..eq], &field[eq + 1..]));
            buf = &buf[4 + len..];
        }
        Ok(Self(out))
    }

    fn get(&self, name: &str) -> Result<&'a [u8], String> {
        self.0
            .iter()
            .find(|(k, _)| *k == name.as_bytes())
            .map(|(_, v)| *v)
            .ok_or_else(|| format!("header field `{name}` is missing"))
    }

    /// The record type.
    pub(crate) fn op(&self) -> Result<u8, String> {
        match self.get("op")? {
            [op] => Ok(*op),
            v => Err(format!("field `op` has {} bytes, expected 1", v.len())),
        }
    }

    /// A `u32` field.
    pub(crate) fn u32(&self, name: &str) -> Result<u32, String> {
        let v = self.get(name)?;
        <[u8; 4]>::try_from(v)
            .map(u32::from_le_bytes)
            .map_err(|_| format!("field `{name}` has {} bytes, expected 4", v.len()))
    }

    /// A `u64` field.
    pub(crate) fn u64(&self, name: &str) -> Result<u64, String> {
        let v = self.get(name)?;
        <[u8; 8]>::try_from(v)
            .map(u64::from_le_bytes)
            .map_err(|_| format!("field `{name}` has {} bytes, expected 8", v.len()))
    }

    /// A ROS time field (`sec u32, nsec u32`), nanoseconds.
    pub(crate) fn time(&self, name: &str) -> Result<u64, String> {
        let ns = self.u64(name)?;
        Ok((ns & 0xffff_ffff) * 1_000_000_000 + (ns >> 32))
    }

    /// A text field.
    pub(crate) fn str(&self, name: &str) -> Result<&'a str, String> {
        std::str::from_utf8(self.get(name)?).map_err(|_| format!("field `{name}` is not UTF-8"))
    }
}

fn le_u32(b: &[u8]) -> Option<u32> {
    b.get(..4)
        .and_then(|s| <[u8; 4]>::try_from(s).ok())
        .map(u32::from_le_bytes)
}

/// A record read from a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Record {
    pub header: Vec<u8>,
    pub data: Vec<u8>,
}

impl Record {
    /// Reads the record at the reader's position; `None` at the end of the input. `max_len`
    /// (the bytes left in the file) bounds both lengths, so a corrupt length never allocates.
    pub(crate) fn read(r: &mut impl Read, max_len: u64) -> Result<Option<Self>, String> {
        let mut len = [0u8; 4];
        match read_full(r, &mut len)? {
            0 => return Ok(None),
            4 => {}
            n => {
                return Err(format!(
                    "the file ends {n} bytes into a record header length"
                ))
            }
        }
        let header = read_block(
            r,
            u32::from_le_bytes(len),
            max_len.saturating_sub(4),
            "header",
        )?;
        let left = max_len.saturating_sub(8 + header.len() as u64);
        if read_full(r, &mut len)? != 4 {
            return Err("the file ends before the record's data length".into());
        }
        let data = read_block(r, u32::from_le_bytes(len), left, "data")?;
        Ok(Some(Self { header, data }))
    }

    /// The header fields.
    pub(crate) fn fields(&self) -> Result<Fields<'_>, String> {
        Fields::parse(&self.header)
    }
}

fn read_full(r: &mut impl Read, buf: &mut [u8]) -> Result<usize, String> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e.to_string()),
        }
    }
    Ok(n)
}

fn read_block(r: &mut impl Read, len: u32, max: u64, what: &str) -> Result<Vec<u8>, String> {
    if u64::from(len) > max {
        return Err(format!(
            "record {what} of {len} bytes but only {max} bytes are left in the file \
             (truncated or corrupt)"
        ));
    }
    let mut buf = vec![0u8; len as usize];
    let n = read_full(r, &mut buf)?;
    if n != buf.len() {
        return Err(format!(
            "the file ends {n} bytes into a {len}-byte record {what}"
        ));
    }
    Ok(buf)
}

/// The records inside a decompressed chunk: `(offset, fields, data)`.
pub(crate) fn records_in(
    buf: &[u8],
) -> impl Iterator<Item = Result<(usize, Fields<'_>, &[u8]), String>> {
    let mut pos = 0usize;
    let mut failed = false;
    std::iter::from_fn(move || {
        if failed || pos >= buf.len() {
            return None;
        }
        let at = pos;
        let r = (|| {
            let block = |p: usize| -> Result<(&[u8], usize), String> {
                let len = le_u32(&buf[p..]).ok_or("record length cut short")? as usize;
                let body = buf
                    .get(p + 4..p + 4 + len)
                    .ok_or_else(|| format!("record part of {len} bytes runs past the chunk"))?;
                Ok((body, p + 4 + len))
            };
            let (header, p) = block(at)?;
            let (data, p) = block(p)?;
            pos = p;
            Ok((at, Fields::parse(header)?, data))
        })();
        failed = r.is_err();
        Some(r.map_err(|e: String| format!("record at chunk offset {at}: {e}")))
    })
}

/// The uncompressed contents of a chunk (`compression` = `none`, `bz2` or `lz4`), which must
/// be `size` bytes long.
pub(crate) fn decompress(compression: &str, data: &[u8], size: u32) -> Result<Vec<u8>, String> {
    if size as usize > RECORD_LIMIT {
        return Err(format!(
            "the chunk declares {size} bytes uncompressed, over the {} MiB chunk limit",
            RECORD_LIMIT >> 20
        ));
    }
    let limit = u64::from(size) + 1;
    let mut out = Vec::with_capacity(initial_capacity(data.len(), size));
    let result = match compression {
        "none" => {
            out.extend_from_slice(data);
            Ok(())
        }
        "bz2" => bzip2::read::BzDecoder::new(data)
            .take(limit)
            .read_to_end(&mut out)
            .map(drop),
        "lz4" => lz4::Decoder::new(data)
            .and_then(|d| d.take(limit).read_to_end(&mut out))
            .map(drop),
        other => return Err(format!("unknown chunk compression `{other}`")),
    };
    result.map_err(|e| format!("{compression} decompression failed: {e}"))?;
    if out.len() != size as usize {
        return Err(format!(
            "{compression} data decompressed to {} bytes but the chunk header says {size}",
            out.len()
        ));
    }
    Ok(out)
}

/// Compression ratios up to this are reserved in one go; beyond it the buffer grows with the
/// bytes the decoder really gives.
const MAX_RESERVED_RATIO: usize = 8;

/// What to reserve for a chunk of `compressed` bytes that declares `size`: the declared size
/// when the compressed data could plausibly expand to it, else a bound from the data, so a
/// 200-byte chunk claiming 4 GiB reserves 64 KiB, not the claim.
fn initial_capacity(compressed: usize, size: u32) -> usize {
    let plausible = compressed.saturating_mul(MAX_RESERVED_RATIO).max(64 << 10);
    (size as usize).min(plausible)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Serialises a record from `(name, value)` fields and data.
    pub fn record(fields: &[(&str, &[u8])], data: &[u8]) -> Vec<u8> {
        let mut header = Vec::new();
        for (k, v) in fields {
            header.extend(((k.len() + 1 + v.len()) as u32).to_le_bytes());
            header.extend(k.as_bytes());
            header.push(b'=');
            header.extend(*v);
        }
        let mut out = (header.len() as u32).to_le_bytes().to_vec();
        out.extend(header);
        out.extend((data.len() as u32).to_le_bytes());
        out.extend(data);
        out
    }

    #[test]
    fn fields_and_records() {
        let time = (5u64 << 32) | 3; // nsec 5, sec 3
        let bytes = record(
            &[
                ("op", &[op::MSG_DATA]),
                ("conn", &7u32.to_le_bytes()),
                ("time", &time.to_le_bytes()),
            ],
            b"payload",
        );
        let rec = Record::read(&mut bytes.as_slice(), bytes.len() as u64)
            .unwrap()
            .unwrap();
        let f = rec.fields().unwrap();
        assert_eq!(f.op().unwrap(), op::MSG_DATA);
        assert_eq!(f.u32("conn").unwrap(), 7);
        assert_eq!(f.time("time").unwrap(), 3_000_000_005);
        assert!(f.u64("conn").unwrap_err().contains("4 bytes, expected 8"));
        assert!(f.str("topic").unwrap_err().contains("missing"));
        assert_eq!(rec.data, b"payload");
        assert_eq!(Record::read(&mut &[][..], 0).unwrap(), None);
        let e = Record::read(&mut &bytes[..bytes.len() - 2], bytes.len() as u64 - 2).unwrap_err();
        assert!(e.contains("record data of 7 bytes"), "{e}");
        let inner: Vec<_> = records_in(&bytes).collect();
        assert_eq!(inner.len(), 1);
        let (at, f, data) = inner[0].as_ref().unwrap();
        assert_eq!(
            (*at, f.u32("conn").unwrap(), *data),
            (0, 7, &b"payload"[..])
        );
        let cut: Vec<_> = records_in(&bytes[..bytes.len() - 1]).collect();
        assert!(cut[0].as_ref().unwrap_err().contains("chunk offset 0"));
    }

    #[test]
    fn chunk_codecs() {
        use std::io::Write;
        let plain = b"hello hello hello hello".to_vec();
        let mut bz = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::fast());
        bz.write_all(&plain).unwrap();
        let bz = bz.finish().unwrap();
        let mut lz = lz4::EncoderBuilder::new().build(Vec::new()).unwrap();
        lz.write_all(&plain).unwrap();
        let (lz, done) = lz.finish();
        done.unwrap();
        let n = plain.len() as u32;
        for (c, data) in [("none", &plain), ("bz2", &bz), ("lz4", &lz)] {
            assert_eq!(decompress(c, data, n).unwrap(), plain, "{c}");
            assert!(decompress(c, data, n + 1)
                .unwrap_err()
                .contains("header says"));
        }
        assert!(decompress("bz2", &plain, n).unwrap_err().contains("bz2"));
        assert!(decompress("zip", &plain, n).unwrap_err().contains("zip"));
        let e = decompress("lz4", &lz, u32::MAX).unwrap_err();
        assert!(e.contains("over the 512 MiB chunk limit"), "{e}");
        // A chunk that really expands far beyond the reserved ratio still reads whole.
        let zeros = vec![0u8; 4 << 20];
        let mut lz = lz4::EncoderBuilder::new().build(Vec::new()).unwrap();
        lz.write_all(&zeros).unwrap();
        let (lz, done) = lz.finish();
        done.unwrap();
        assert!(lz.len() * MAX_RESERVED_RATIO < zeros.len());
        assert_eq!(decompress("lz4", &lz, zeros.len() as u32).unwrap(), zeros);
    }

    #[test]
    fn a_huge_declared_size_is_not_reserved() {
        assert_eq!(initial_capacity(200, u32::MAX), 64 << 10);
        assert_eq!(initial_capacity(1 << 20, u32::MAX), 8 << 20);
        // Plausible claims are reserved exactly.
        assert_eq!(initial_capacity(1 << 20, 3 << 20), 3 << 20);
        assert_eq!(initial_capacity(10, 100), 100);
    }
}
