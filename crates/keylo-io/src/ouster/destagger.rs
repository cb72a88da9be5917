//! Staggered packet columns → the destaggered, organised [`LidarFrame`]: every channel
//! shifted row by row as ouster-sdk's `destagger` does, XYZ from the lookup table, and the
//! firing time of every pixel.

use std::sync::Arc;

use keylo_core::{BeamGeometry, LidarFrame};
use nalgebra::Point3;

use super::metadata::OusterMetadata;
use super::packet::RawFrame;
use super::xyz::XyzLut;
use crate::cloud::organised::column_times;

/// Which return of a dual-return profile fills the frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Return {
    /// The strongest return (the only one of single-return profiles).
    Strongest,
    /// The second strongest return.
    Second,
}

/// Destaggers the frames of one sensor.
#[derive(Debug, Clone)]
pub struct Destaggerer {
    rows: usize,
    cols: usize,
    /// Per row, the shift in `0..cols`.
    shifts: Vec<usize>,
    /// Shift whose columns best stand for a destaggered column's time (the median row's).
    median_shift: usize,
    lut: XyzLut,
    beams: Arc<BeamGeometry>,
}

impl Destaggerer {
    /// The destaggerer of `meta`'s sensor.
    pub fn new(meta: &OusterMetadata) -> Self {
        let (rows, cols) = (meta.pixels_per_column, meta.columns_per_frame);
        let shifts: Vec<usize> = meta
            .pixel_shift_by_row
            .iter()
            .map(|s| s.rem_euclid(cols as i64) as usize)
            .collect();
        let mut sorted = shifts.clone();
        sorted.sort_unstable();
        let median_shift = sorted.get(sorted.len() / 2).copied().unwrap_or(0);
        let beams = Arc::new(BeamGeometry {
            model: if meta.prod_line.is_empty() {
                format!("Ouster {rows}-beam")
            } else {
                meta.prod_line.clone()
            },
            altitude_deg: meta.beam_altitude_angles.clone(),
            azimuth_deg: meta.beam_azimuth_angles.clone(),
            origin_to_beam_mm: meta.lidar_origin_to_beam_origin_mm,
            columns_per_frame: cols,
            frame_rate_hz: f64::from(meta.fps),
        });
        Self {
            rows,
            cols,
            shifts,
            median_shift,
            lut: XyzLut::new(meta),
            beams,
        }
    }

    /// The staggered column that destaggered pixel `(row, col)` comes from.
    #[inline]
    fn source_column(&self, row: usize, col: usize) -> usize {
        (col + self.cols - self.shifts[row]) % self.cols
    }

    /// The destaggered frame of `raw`, numbered `index`. Pixels of missing columns and
    /// pixels without a return (range 0) are invalid. Range is in metres.
    pub fn frame(&self, raw: &RawFrame, index: u64, which: Return) -> LidarFrame {
        let (range, signal, reflectivity) = match which {
            Return::Second if !raw.range2_mm.is_empty() => {
                (&raw.range2_mm, &raw.signal2, &raw.reflectivity2)
            }
            _ => (&raw.range_mm, &raw.signal, &raw.reflectivity),
        };
        let staggered_times = self.staggered_times(raw);
        let timestamp = staggered_times.first().copied().unwrap_or(0.0);
        let mut f = LidarFrame::empty(
            index,
            timestamp,
            self.rows,
            self.cols,
            Arc::clone(&self.beams),
        );
        let mut pixel_times = vec![timestamp; self.rows * self.cols];
        for r in 0..self.rows {
            for c in 0..self.cols {
                let m = self.source_column(r, c);
                let (src, dst) = (r * self.cols + m, r * self.cols + c);
                pixel_times[dst] = staggered_times[m];
                f.signal[dst] = signal[src] as f32;
                f.reflectivity[dst] = reflectivity[src] as f32;
                f.near_ir[dst] = raw.near_ir[src] as f32;
                let Some(p) = self.lut.point(r, m, range[src]) else {
                    continue;
                };
                f.range[dst] = range[src] as f32 * 1e-3;
                f.points[dst] = Point3::new(p.x as f32, p.y as f32, p.z as f32);
                f.valid[dst] = raw.column_valid[m];
            }
        }
        f.column_times = (0..self.cols)
            .map(|c| staggered_times[(c + self.cols - self.median_shift) % self.cols])
            .collect();
        f.pixel_times = Some(pixel_times);
        f
    }

    /// Seconds of every staggered column; missing columns interpolated from their neighbours.
    fn staggered_times(&self, raw: &RawFrame) -> Vec<f64> {
        let valid = || (0..self.cols).filter(|&m| raw.column_valid[m]);
        let Some(t0) = valid().map(|m| raw.column_ns[m]).min() else {
            return vec![0.0; self.cols];
        };
        let samples = valid().map(|m| (m, raw.column_ns[m].saturating_sub(t0) as f64 * 1e-9));
        column_times(t0 as f64 * 1e-9, self.cols, samples)
    }
}
