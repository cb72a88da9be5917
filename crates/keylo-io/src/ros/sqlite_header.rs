//! What the 100-byte header of an SQLite database says about the file's length: a copy cut
//! short (a recording copied off a full disk, a download stopped early) is named as such
//! instead of SQLite's bare "database disk image is malformed".

use std::io::Read;
use std::path::Path;

/// Bytes of the database header.
const HEADER: usize = 100;

/// Why the file at `path` is shorter than its header says, if it is.
pub(crate) fn cut_short(path: &Path) -> std::io::Result<Option<String>> {
    let file = std::fs::File::open(path)?;
    let len = file.metadata()?.len();
    let mut head = Vec::with_capacity(HEADER);
    file.take(HEADER as u64).read_to_end(&mut head)?;
    Ok(judge(&head, len))
}

/// `head`: the first bytes of a file of `len` bytes.
fn judge(head: &[u8], len: u64) -> Option<String> {
    let Ok(h) = <&[u8; HEADER]>::try_from(head) else {
        return Some(format!(
            "the file is cut short: {len} bytes end inside the {HEADER}-byte sqlite3 header"
        ));
    };
    let page_size = match u16::from_be_bytes([h[16], h[17]]) {
        1 => 65536,
        n => u64::from(n),
    };
    if !page_size.is_power_of_two() || !(512..=65536).contains(&page_size) {
        return None; // SQLite names a bad header itself
    }
    let be32 = |at: usize| u32::from_be_bytes([h[at], h[at + 1], h[at + 2], h[at + 3]]);
    // The page count at byte 28 holds when the change counter matches "version valid for".
    let pages = u64::from(be32(28));
    let declared = (pages > 0 && be32(24) == be32(92)).then_some(pages * page_size);
    match declared {
        Some(want) if want > len => Some(format!(
            "the file is cut short: {len} bytes, its header declares {pages} pages of \
             {page_size} bytes ({want} bytes)"
        )),
        _ if !len.is_multiple_of(page_size) => Some(format!(
            "the file is cut short: {len} bytes is not a whole number of {page_size}-byte pages"
        )),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(page_size: u16, pages: u32, counters_match: bool) -> Vec<u8> {
        let mut h = vec![0u8; HEADER];
        h[..16].copy_from_slice(b"SQLite format 3\0");
        h[16..18].copy_from_slice(&page_size.to_be_bytes());
        h[24..28].copy_from_slice(&7u32.to_be_bytes());
        h[28..32].copy_from_slice(&pages.to_be_bytes());
        let valid_for: u32 = if counters_match { 7 } else { 8 };
        h[92..96].copy_from_slice(&valid_for.to_be_bytes());
        h
    }

    #[test]
    fn lengths_against_the_header() {
        assert_eq!(judge(&header(4096, 3, true), 3 * 4096), None);
        let e = judge(&header(4096, 3, true), 2 * 4096).unwrap();
        assert!(e.contains("3 pages of 4096 bytes (12288 bytes)"), "{e}");
        // A stale page count is not trusted; the length must still be whole pages.
        assert_eq!(judge(&header(4096, 3, false), 2 * 4096), None);
        let e = judge(&header(1, 1, true), 65535).unwrap();
        assert!(e.contains("65536 bytes (65536 bytes)"), "{e}");
        let e = judge(&header(4096, 0, true), 4097).unwrap();
        assert!(e.contains("not a whole number of 4096-byte pages"), "{e}");
        assert!(judge(&header(4096, 1, true)[..40], 40)
            .unwrap()
            .contains("inside the 100-byte"));
        assert_eq!(judge(&header(1000, 1, true), 1), None, "SQLite's to name");
    }
}
