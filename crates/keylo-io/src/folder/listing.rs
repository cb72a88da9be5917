//! The frame files of a folder in natural order, and the time stamps their names carry.

use std::cmp::Ordering;
use std::path::{Path, PathBuf};

use crate::IoError;

/// Compares names so that embedded numbers sort by value: `2.pcd` < `10.pcd`.
///
/// Runs of ASCII digits compare as numbers (equal values: fewer leading zeros first), other
/// bytes compare as bytes.
///
/// ```
/// use keylo_io::folder::natural_cmp;
/// let mut names = vec!["scan10.ply", "scan2.ply", "scan1.ply"];
/// names.sort_by(|a, b| natural_cmp(a, b));
/// assert_eq!(names, ["scan1.ply", "scan2.ply", "scan10.ply"]);
/// ```
pub fn natural_cmp(a: &str, b: &str) -> Ordering {
    let (mut a, mut b) = (a.as_bytes(), b.as_bytes());
    loop {
        match (a.first(), b.first()) {
            (None, None) => return Ordering::Equal,
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
            (Some(x), Some(y)) if x.is_ascii_digit() && y.is_ascii_digit() => {
                let (da, rest_a) = split_digits(a);
                let (db, rest_b) = split_digits(b);
                let (va, vb) = (trim_zeros(da), trim_zeros(db));
                let order = va
                    .len()
                    .cmp(&vb.len())
                    .then_with(|| va.cmp(vb))
                    .then_with(|| da.len().cmp(&db.len()));
                if order != Ordering::Equal {
                    return order;
                }
                (a, b) = (rest_a, rest_b);
            }
            (Some(x), Some(y)) => {
                if x != y {
                    return x.cmp(y);
                }
                (a, b) = (&a[1..], &b[1..]);
            }
        }
    }
}

fn split_digits(s: &[u8]) -> (&[u8], &[u8]) {
    let n = s.iter().take_while(|c| c.is_ascii_digit()).count();
    s.split_at(n)
}

fn trim_zeros(s: &[u8]) -> &[u8] {
    let n = s.iter().take_while(|&&c| c == b'0').count();
    &s[n..]
}

/// The files of `dir` whose extension is one of `exts` (case-insensitive), in natural order
/// of their names.
pub fn list_files(dir: &Path, exts: &[&str]) -> Result<Vec<PathBuf>, IoError> {
    let entries = std::fs::read_dir(dir).map_err(|e| IoError::io(dir, e))?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| has_extension(p, exts) && p.is_file())
        .collect();
    files.sort_by(|a, b| natural_cmp(&file_name(a), &file_name(b)));
    Ok(files)
}

/// True when `dir` holds at least one file with one of the extensions `exts`.
pub fn has_files(dir: &Path, exts: &[&str]) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries
            .filter_map(Result::ok)
            .any(|e| has_extension(&e.path(), exts))
    })
}

/// True when the extension of `path` is one of `exts`, ignoring case.
pub fn has_extension(path: &Path, exts: &[&str]) -> bool {
    path.extension()
        .and_then(|x| x.to_str())
        .is_some_and(|x| exts.iter().any(|e| x.eq_ignore_ascii_case(e)))
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The time stamp in a file name, seconds, or `None` when the name is not a stamp.
///
/// The name without its extension must be a number: with a decimal point it is seconds
/// (`1698412345.123456.pcd`, `12.5.ply`); an integer is read by magnitude as nanoseconds
/// (≥ 1e17), microseconds (≥ 1e14), milliseconds (≥ 1e11) or seconds (≥ 1e8, epoch
/// seconds). Smaller integers (`000042.pcd`) are frame numbers, not stamps.
pub fn name_stamp(path: &Path) -> Option<f64> {
    let stem = path.file_stem()?.to_str()?;
    let digits = |s: &str| s.bytes().all(|c| c.is_ascii_digit());
    if let Some((whole, frac)) = stem.split_once('.') {
        let ok = !whole.is_empty() && !frac.is_empty() && digits(whole) && digits(frac);
        return ok.then(|| stem.parse().ok()).flatten();
    }
    if stem.is_empty() || !digits(stem) {
        return None;
    }
    let v: u128 = stem.parse().ok()?;
    let per_second: u128 = [(1e17, 1e9), (1e14, 1e6), (1e11, 1e3), (1e8, 1.0)]
        .into_iter()
        .find(|&(min, _)| v as f64 >= min)
        .map(|(_, n)| n as u128)?;
    // Whole seconds and the fraction apart: epoch nanoseconds exceed f64's integer range.
    Some((v / per_second) as f64 + (v % per_second) as f64 / per_second as f64)
}

/// Frame times of `files`: their name stamps when every name is one (the files are then
/// re-sorted by stamp), else `index / frame_rate_hz`. The flag says which was used.
pub fn frame_stamps(files: &mut [PathBuf], frame_rate_hz: f64) -> (Vec<f64>, bool) {
    let stamps: Option<Vec<f64>> = files.iter().map(|f| name_stamp(f)).collect();
    match stamps {
        Some(s) if !s.is_empty() => {
            let mut pairs: Vec<(f64, PathBuf)> = s.into_iter().zip(files.iter().cloned()).collect();
            pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (slot, (_, f)) in files.iter_mut().zip(&pairs) {
                *slot = f.clone();
            }
            (pairs.into_iter().map(|(t, _)| t).collect(), true)
        }
        _ => (index_stamps(files.len(), frame_rate_hz), false),
    }
}

/// `index / frame_rate_hz` for `n` frames.
pub fn index_stamps(n: usize, frame_rate_hz: f64) -> Vec<f64> {
    (0..n).map(|i| i as f64 / frame_rate_hz).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_sort_by_value() {
        let mut v = vec!["a10", "a9", "a09", "b1", "a", "a1x", "a1"];
        v.sort_by(|a, b| natural_cmp(a, b));
        assert_eq!(v, ["a", "a1", "a1x", "a9", "a09", "a10", "b1"]);
        assert_eq!(natural_cmp("000010.bin", "000009.bin"), Ordering::Greater);
    }

    #[test]
    fn stamps_in_names() {
        let s = |n: &str| name_stamp(Path::new(n));
        assert_eq!(s("000042.pcd"), None);
        assert_eq!(s("scan_1.pcd"), None);
        assert_eq!(s("12.5.ply"), Some(12.5));
        assert_eq!(s("1698412345.pcd"), Some(1698412345.0));
        assert_eq!(s("1698412345123.pcd"), Some(1698412345.123));
        let ns = s("1698412345123456789.pcd").unwrap_or_default();
        assert!((ns - 1_698_412_345.123_456_7).abs() < 1e-6);
        assert_eq!(s("1.2.3.pcd"), None);
        assert_eq!(s(".5.pcd"), None);
    }

    #[test]
    fn stamped_names_resort_by_time_and_others_use_the_rate() {
        let mut files: Vec<PathBuf> = ["10.25.pcd", "10.5.pcd", "9.75.pcd"]
            .iter()
            .map(PathBuf::from)
            .collect();
        let (t, named) = frame_stamps(&mut files, 10.0);
        assert!(named);
        assert_eq!(t, vec![9.75, 10.25, 10.5]);
        assert_eq!(files[0], PathBuf::from("9.75.pcd"));
        let mut plain = vec![PathBuf::from("a.pcd"), PathBuf::from("10.5.pcd")];
        let (t, named) = frame_stamps(&mut plain, 4.0);
        assert!(!named);
        assert_eq!(t, vec![0.0, 0.25]);
    }
}
