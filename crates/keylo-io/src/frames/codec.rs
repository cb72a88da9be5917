//! Binary layout of one `.klf` frame (all little-endian, `n = rows·cols`, row-major):
//!
//! | bytes | field |
//! |---|---|
//! | 4 | magic `KLF1` |
//! | 4 + 4 | rows, cols (u32) |
//! | 8 | frame index (u64) |
//! | 8 | timestamp of the first column, s (f64) |
//! | 8·cols | column times, s (f64) |
//! | 4·n ×4 | range (m), signal, reflectivity, near-IR (f32 grids) |
//! | 12·n | x y z per pixel, sensor frame, m (f32) |
//! | n | valid flag (u8, 0 or 1) |

use std::path::Path;
use std::sync::Arc;

use keylo_core::{BeamGeometry, LidarFrame};
use nalgebra::Point3;

use crate::IoError;

/// File magic.
pub const MAGIC: &[u8; 4] = b"KLF1";

/// Largest grid a frame file may declare (pixels), far above any real sensor.
pub const MAX_PIXELS: usize = 1 << 26;

/// Size in bytes of a frame file; `None` for a grid larger than [`MAX_PIXELS`].
pub fn encoded_len(rows: usize, cols: usize) -> Option<usize> {
    let n = rows.checked_mul(cols).filter(|n| *n <= MAX_PIXELS)?;
    Some(4 + 8 + 8 + 8 + 8 * cols + 16 * n + 12 * n + n)
}

/// Serialises a frame.
pub fn encode(frame: &LidarFrame) -> Vec<u8> {
    let mut out = Vec::with_capacity(encoded_len(frame.rows, frame.cols).unwrap_or(0));
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&(frame.rows as u32).to_le_bytes());
    out.extend_from_slice(&(frame.cols as u32).to_le_bytes());
    out.extend_from_slice(&frame.index.to_le_bytes());
    out.extend_from_slice(&frame.timestamp.to_le_bytes());
    frame
        .column_times
        .iter()
        .for_each(|t| out.extend_from_slice(&t.to_le_bytes()));
    for grid in [
        &frame.range,
        &frame.signal,
        &frame.reflectivity,
        &frame.near_ir,
    ] {
        grid.iter()
            .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
    }
    for p in &frame.points {
        [p.x, p.y, p.z]
            .iter()
            .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
    }
    out.extend(frame.valid.iter().map(|v| u8::from(*v)));
    out
}

/// A little-endian reader over a byte slice.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let mut a = [0u8; N];
        a.copy_from_slice(&self.bytes[self.at..self.at + N]);
        self.at += N;
        a
    }
    /// The next `n` bytes (the caller has checked the length).
    fn slice(&mut self, n: usize) -> &[u8] {
        let s = &self.bytes[self.at..self.at + n];
        self.at += n;
        s
    }
    fn f32s(&mut self, n: usize) -> Vec<f32> {
        self.slice(4 * n).chunks_exact(4).map(f32_le).collect()
    }
    fn points(&mut self, n: usize) -> Vec<Point3<f32>> {
        self.slice(12 * n)
            .chunks_exact(12)
            .map(|c| Point3::new(f32_le(&c[..4]), f32_le(&c[4..8]), f32_le(&c[8..])))
            .collect()
    }
}

/// A little-endian f32 from 4 bytes.
#[inline]
fn f32_le(b: &[u8]) -> f32 {
    f32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

/// Parses a frame file's bytes; `path` names it in errors.
pub fn decode(path: &Path, bytes: &[u8], beams: &Arc<BeamGeometry>) -> Result<LidarFrame, IoError> {
    if bytes.len() < 12 || &bytes[..4] != MAGIC {
        return Err(IoError::format(
            path,
            "not a keylo frame file (magic `KLF1` missing)",
        ));
    }
    let mut r = Reader { bytes, at: 4 };
    let rows = u32::from_le_bytes(r.take()) as usize;
    let cols = u32::from_le_bytes(r.take()) as usize;
    let Some(expected) = encoded_len(rows, cols) else {
        return Err(IoError::format(
            path,
            format!("header declares {rows}x{cols} pixels, more than the {MAX_PIXELS} allowed (corrupt)"),
        ));
    };
    if bytes.len() != expected {
        return Err(IoError::format(
            path,
            format!(
                "{} bytes, expected {expected} for {rows}x{cols} (truncated or corrupt)",
                bytes.len()
            ),
        ));
    }
    let n = rows * cols;
    let index = u64::from_le_bytes(r.take());
    let timestamp = f64::from_le_bytes(r.take());
    let column_times = (0..cols).map(|_| f64::from_le_bytes(r.take())).collect();
    let (range, signal, reflectivity, near_ir) = (r.f32s(n), r.f32s(n), r.f32s(n), r.f32s(n));
    let points = r.points(n);
    let valid = bytes[r.at..].iter().map(|b| *b != 0).collect();
    Ok(LidarFrame {
        index,
        timestamp,
        rows,
        cols,
        column_times,
        pixel_times: None,
        range,
        signal,
        reflectivity,
        near_ir,
        points,
        valid,
        beams: Arc::clone(beams),
        scan: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> LidarFrame {
        let beams = Arc::new(BeamGeometry {
            model: "t".into(),
            altitude_deg: vec![1.0, 0.0],
            azimuth_deg: vec![0.0, 0.0],
            origin_to_beam_mm: 0.0,
            columns_per_frame: 3,
            frame_rate_hz: 10.0,
            column_lag_by_row: Vec::new(),
        });
        let mut f = LidarFrame::empty(7, 1.5, 2, 3, beams);
        f.range[2] = 4.0;
        f.signal[3] = 9.0;
        f.points[5] = Point3::new(1.0, -2.0, 3.5);
        f.valid[5] = true;
        f.column_times = vec![1.5, 1.53, 1.56];
        f
    }

    #[test]
    fn round_trips() {
        let f = frame();
        let bytes = encode(&f);
        assert_eq!(Some(bytes.len()), encoded_len(2, 3));
        let g = decode(Path::new("x.klf"), &bytes, &f.beams).unwrap();
        assert_eq!(f, g);
    }

    #[test]
    fn truncated_and_foreign_files_are_errors_naming_the_file() {
        let f = frame();
        let bytes = encode(&f);
        let e = decode(Path::new("a.klf"), &bytes[..bytes.len() - 1], &f.beams).unwrap_err();
        assert!(e.to_string().starts_with("a.klf:") && e.to_string().contains("truncated"));
        let e = decode(Path::new("b.klf"), b"hello world!", &f.beams).unwrap_err();
        assert!(e.to_string().contains("magic"));
        let e = decode(Path::new("c.klf"), b"", &f.beams).unwrap_err();
        assert!(e.to_string().contains("magic"));
    }
}
