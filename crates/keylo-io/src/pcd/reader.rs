//! One `.pcd` file to a [`RawCloud`], with `pcd-rs` doing the parsing (ascii, binary and
//! binary_compressed).
//!
//! Where the crate falls short, this file does the work itself:
//! - two checks run before `pcd-rs` sees a file: its error for an unreadable TYPE/SIZE pair
//!   does not name the field, and its binary_compressed path indexes out of bounds (a panic)
//!   when the sizes in the file disagree with the header;
//! - `binary` data is read here, straight from the bytes into columns: `pcd-rs` yields every
//!   point as a `DynRecord` (a vector of per-field vectors, a dozen allocations per point),
//!   15× slower than this on a 125k-point scan (65 ms against 4 ms). ascii and
//!   binary_compressed (LZF, which `pcd-rs` keeps private) still go through `pcd-rs`.

use std::io::Cursor;
use std::path::Path;

use pcd_rs::{DataKind, DynReader, Field, PcdMeta, ValueKind};

use crate::cloud::RawCloud;
use crate::folder::fields::{FieldInfo, FieldMap, FieldOptions};
use crate::folder::Columns;
use crate::IoError;

/// The header of `path` and the fields keylo sees (padding `_` fields left out).
pub fn pcd_fields(path: &Path) -> Result<Vec<FieldInfo>, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    let (meta, _) = header(path, &bytes)?;
    Ok(fields(&meta))
}

/// Reads `path`: the mapped fields (x, y, z required; other fields ignored), organised as
/// `HEIGHT × WIDTH` when `HEIGHT > 1`. `stamp` is the cloud time unless the points carry an
/// absolute clock.
pub fn read_pcd(path: &Path, stamp: f64, options: &FieldOptions) -> Result<RawCloud, IoError> {
    let err = |m: String| IoError::format(path, m);
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    let (meta, data_start) = header(path, &bytes)?;
    let body = bytes.get(data_start..).unwrap_or_default();
    check_body(&meta, body).map_err(err)?;
    let grid = grid(&meta).map_err(err)?;
    let fields = fields(&meta);
    let map = FieldMap::new(&fields).map_err(|e| err(e.to_string()))?;
    let n = usize::try_from(meta.num_points).unwrap_or(usize::MAX);
    let mut columns = Columns::new(&map, n.min(1 << 20));
    if meta.data == DataKind::Binary {
        read_binary(&meta, body, &mut columns);
    } else {
        let reader = DynReader::from_bytes(&bytes).map_err(|e| err(format!("PCD header: {e}")))?;
        for (i, record) in reader.enumerate() {
            let record = record.map_err(|e| err(format!("point {i} of the {n} in POINTS: {e}")))?;
            columns.push(|p| record.0.get(p).map_or(f64::NAN, value));
        }
    }
    if columns.len() != n {
        return Err(err(format!(
            "the header declares {n} points but the data holds {}",
            columns.len()
        )));
    }
    columns.finish(stamp, grid, options).map_err(err)
}

/// The parsed header and the offset of the data after it.
fn header(path: &Path, bytes: &[u8]) -> Result<(PcdMeta, usize), IoError> {
    let end = header_end(bytes)
        .ok_or_else(|| IoError::format(path, "not a PCD file: no `DATA` line ends a header"))?;
    let text = String::from_utf8_lossy(&bytes[..end]);
    check_types(&text).map_err(|m| IoError::format(path, m))?;
    let meta = PcdMeta::from_reader(Cursor::new(&bytes[..end]))
        .map_err(|e| IoError::format(path, format!("PCD header: {e}")))?;
    Ok((meta, end))
}

/// Offset just past the `DATA ...` line (header lines are ASCII).
fn header_end(bytes: &[u8]) -> Option<usize> {
    let mut start = 0;
    while start < bytes.len() {
        let end = bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |p| start + p + 1);
        let line = String::from_utf8_lossy(&bytes[start..end]);
        let key = line.split_whitespace().next().unwrap_or_default();
        if key.eq_ignore_ascii_case("DATA") {
            return Some(end);
        }
        start = end;
    }
    None
}

/// Every field's TYPE/SIZE pair must be one keylo reads; the error names the field.
fn check_types(header: &str) -> Result<(), String> {
    let entry = |key: &str| -> Vec<String> {
        header
            .lines()
            .map(|l| l.split('#').next().unwrap_or_default())
            .map(|l| l.split_whitespace().collect::<Vec<_>>())
            .find(|t| t.first().is_some_and(|k| k.eq_ignore_ascii_case(key)))
            .map(|t| t[1..].iter().map(|s| s.to_string()).collect())
            .unwrap_or_default()
    };
    let mut names = entry("FIELDS");
    if names.is_empty() {
        names = entry("COLUMNS");
    }
    let (sizes, types) = (entry("SIZE"), entry("TYPE"));
    for ((name, size), ty) in names.iter().zip(&sizes).zip(&types) {
        let ok = match ty.to_ascii_uppercase().as_str() {
            "I" | "U" => matches!(size.as_str(), "1" | "2" | "4" | "8"),
            "F" => matches!(size.as_str(), "4" | "8"),
            _ => false,
        };
        if !ok {
            return Err(format!(
                "field `{name}` has TYPE {ty} SIZE {size}, which keylo cannot read \
                 (readable: I and U of size 1, 2, 4 or 8; F of size 4 or 8)"
            ));
        }
    }
    Ok(())
}

/// The data must hold what the header declares (binary), and a compressed block must
/// unpack to exactly that.
fn check_body(meta: &PcdMeta, body: &[u8]) -> Result<(), String> {
    let record: u64 = meta
        .field_defs
        .iter()
        .map(|f| f.kind.byte_size() as u64 * f.count)
        .sum();
    let points = meta.num_points;
    let need = points.saturating_mul(record);
    let have = body.len() as u64;
    match meta.data {
        DataKind::Ascii => Ok(()),
        DataKind::Binary if have < need => Err(format!(
            "binary data: the header declares {points} points of {record} bytes ({need} bytes) \
             but the data holds {have} bytes"
        )),
        DataKind::Binary => Ok(()),
        DataKind::BinaryCompressed => {
            let word = |i: usize| {
                body.get(i..i + 4)
                    .and_then(|b| b.try_into().ok())
                    .map(|b: [u8; 4]| u64::from(u32::from_le_bytes(b)))
            };
            let (Some(packed), Some(unpacked)) = (word(0), word(4)) else {
                return Err("binary_compressed data: the 8-byte size prefix is missing".into());
            };
            if unpacked != need {
                return Err(format!(
                    "binary_compressed data unpacks to {unpacked} bytes, but the header \
                     declares {points} points of {record} bytes ({need} bytes)"
                ));
            }
            if packed > have.saturating_sub(8) {
                return Err(format!(
                    "binary_compressed data: {packed} compressed bytes declared, {} present",
                    have.saturating_sub(8)
                ));
            }
            Ok(())
        }
    }
}

/// `(HEIGHT, WIDTH)` for an organised cloud (`HEIGHT > 1`).
fn grid(meta: &PcdMeta) -> Result<Option<(usize, usize)>, String> {
    if meta.height <= 1 {
        return Ok(None);
    }
    if meta.width.checked_mul(meta.height) != Some(meta.num_points) {
        return Err(format!(
            "organised cloud: WIDTH {} × HEIGHT {} is not POINTS {}",
            meta.width, meta.height, meta.num_points
        ));
    }
    let dim = |v: u64| usize::try_from(v).map_err(|_| format!("grid dimension {v} too large"));
    Ok(Some((dim(meta.height)?, dim(meta.width)?)))
}

/// The fields of a record as `pcd-rs` yields them (padding left out).
fn fields(meta: &PcdMeta) -> Vec<FieldInfo> {
    meta.field_defs
        .iter()
        .filter(|f| !f.is_padding())
        .map(|f| FieldInfo {
            name: f.name.clone(),
            integer: !matches!(f.kind, ValueKind::F32 | ValueKind::F64),
            count: usize::try_from(f.count).unwrap_or(usize::MAX),
        })
        .collect()
}

/// Binary data (checked by [`check_body`] to hold every point): each record's non-padding
/// fields, by their byte offset in the record, little-endian.
fn read_binary(meta: &PcdMeta, body: &[u8], columns: &mut Columns) {
    let mut layout = Vec::new();
    let mut offset = 0;
    for f in meta.field_defs.iter() {
        if !f.is_padding() {
            layout.push((offset, f.kind));
        }
        offset += f.kind.byte_size() * usize::try_from(f.count).unwrap_or(usize::MAX);
    }
    if offset == 0 {
        return;
    }
    let n = usize::try_from(meta.num_points).unwrap_or(usize::MAX);
    for record in body.chunks_exact(offset).take(n) {
        columns.push(|p| {
            layout
                .get(p)
                .map_or(f64::NAN, |&(at, kind)| binary_value(record, at, kind))
        });
    }
}

/// The value of `kind` at byte `at` of `record`, NaN when it does not fit.
fn binary_value(record: &[u8], at: usize, kind: ValueKind) -> f64 {
    fn bytes<const N: usize>(r: &[u8], at: usize) -> Option<[u8; N]> {
        r.get(at..at + N)?.try_into().ok()
    }
    let v = match kind {
        ValueKind::U8 => bytes::<1>(record, at).map(|b| f64::from(b[0])),
        ValueKind::I8 => bytes::<1>(record, at).map(|b| f64::from(i8::from_le_bytes(b))),
        ValueKind::U16 => bytes(record, at).map(|b| f64::from(u16::from_le_bytes(b))),
        ValueKind::I16 => bytes(record, at).map(|b| f64::from(i16::from_le_bytes(b))),
        ValueKind::U32 => bytes(record, at).map(|b| f64::from(u32::from_le_bytes(b))),
        ValueKind::I32 => bytes(record, at).map(|b| f64::from(i32::from_le_bytes(b))),
        ValueKind::F32 => bytes(record, at).map(|b| f64::from(f32::from_le_bytes(b))),
        ValueKind::U64 => bytes(record, at).map(|b| u64::from_le_bytes(b) as f64),
        ValueKind::I64 => bytes(record, at).map(|b| i64::from_le_bytes(b) as f64),
        ValueKind::F64 => bytes(record, at).map(f64::from_le_bytes),
    };
    v.unwrap_or(f64::NAN)
}

/// The (first) value of a field as f64.
fn value(field: &Field) -> f64 {
    let first = match field {
        Field::I8(v) => v.first().map(|&x| f64::from(x)),
        Field::I16(v) => v.first().map(|&x| f64::from(x)),
        Field::I32(v) => v.first().map(|&x| f64::from(x)),
        Field::I64(v) => v.first().map(|&x| x as f64),
        Field::U8(v) => v.first().map(|&x| f64::from(x)),
        Field::U16(v) => v.first().map(|&x| f64::from(x)),
        Field::U32(v) => v.first().map(|&x| f64::from(x)),
        Field::U64(v) => v.first().map(|&x| x as f64),
        Field::F32(v) => v.first().map(|&x| f64::from(x)),
        Field::F64(v) => v.first().copied(),
    };
    first.unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unreadable_types_name_the_field() {
        let h = "VERSION 0.7\nFIELDS x y z h\nSIZE 4 4 4 2\nTYPE F F F F\nDATA ascii\n";
        let e = check_types(h).unwrap_err();
        assert!(e.starts_with("field `h` has TYPE F SIZE 2"), "{e}");
        assert!(check_types("FIELDS x\nSIZE 8\nTYPE U\n").is_ok());
        assert!(check_types("FIELDS x\nSIZE 4\nTYPE Q\n").is_err());
    }

    #[test]
    fn header_ends_after_the_data_line() {
        let bytes = b"# c\nVERSION 0.7\nDATA binary\n\x01\x02";
        assert_eq!(header_end(bytes), Some(bytes.len() - 2));
        assert_eq!(header_end(b"VERSION 0.7\n"), None);
    }
}
