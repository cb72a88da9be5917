//! Staggered packet columns → the destaggered, organised [`LidarFrame`]: every channel
//! shifted row by row as ouster-sdk's `destagger` does, XYZ from the lookup table, and the
//! firing time of every pixel.

use std::sync::Arc;

use keylo_core::{BeamGeometry, LidarFrame};
use nalgebra::Point3;
use rayon::prelude::*;

use super::metadata::OusterMetadata;
use super::packet::RawFrame;
use super::xyz::XyzLut;
use crate::cloud::organised::column_times;

/// The staggered channels one frame is destaggered from.
struct Staggered<'a> {
    range: &'a [u32],
    signal: &'a [u32],
    reflectivity: &'a [u32],
    raw: &'a RawFrame,
    times: &'a [f64],
}

/// One destaggered row of every output grid.
struct RowOut<'a> {
    range: &'a mut [f32],
    signal: &'a mut [f32],
    reflectivity: &'a mut [f32],
    near_ir: &'a mut [f32],
    points: &'a mut [Point3<f32>],
    valid: &'a mut [bool],
    times: &'a mut [f64],
}

/// Rows destaggered together (16 u32 values = one cache line of a staggered column).
const ROW_BLOCK: usize = 16;

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
        let mut pixel_times = vec![0.0; self.rows * self.cols];
        let input = Staggered {
            range,
            signal,
            reflectivity,
            raw,
            times: &staggered_times,
        };
        // Rows are independent: destagger blocks of rows in parallel, each into its own
        // output rows. A block reads the staggered (column-major) buffers a cache line per
        // column instead of one value per cache line.
        let block = ROW_BLOCK * self.cols;
        f.range
            .par_chunks_mut(block)
            .zip(f.signal.par_chunks_mut(block))
            .zip(f.reflectivity.par_chunks_mut(block))
            .zip(f.near_ir.par_chunks_mut(block))
            .zip(f.points.par_chunks_mut(block))
            .zip(f.valid.par_chunks_mut(block))
            .zip(pixel_times.par_chunks_mut(block))
            .enumerate()
            .for_each(|(b, ((((((rg, sg), rf), nir), pts), ok), t))| {
                let out = RowOut {
                    range: rg,
                    signal: sg,
                    reflectivity: rf,
                    near_ir: nir,
                    points: pts,
                    valid: ok,
                    times: t,
                };
                self.rows_block(b * ROW_BLOCK, &input, out);
            });
        f.column_times = (0..self.cols)
            .map(|c| staggered_times[(c + self.cols - self.median_shift) % self.cols])
            .collect();
        f.pixel_times = Some(pixel_times);
        f
    }

    /// Destaggers the rows `r0..` that `out` holds: destaggered column `c` of row `r` is
    /// staggered column `m = c - shift(r)` (mod cols). Loops over staggered columns outside
    /// and the block's rows inside, so reads of the column-major input are contiguous.
    fn rows_block(&self, r0: usize, input: &Staggered, out: RowOut) {
        let cols = self.cols;
        let n = out.range.len() / cols.max(1);
        let shifts = &self.shifts[r0..r0 + n];
        for m in 0..cols {
            let base = m * self.rows + r0;
            let valid_col = input.raw.column_valid[m];
            let time = input.times[m];
            for (rb, &shift) in shifts.iter().enumerate() {
                let c = if m + shift >= cols {
                    m + shift - cols
                } else {
                    m + shift
                };
                let (src, dst) = (base + rb, rb * cols + c);
                out.times[dst] = time;
                out.signal[dst] = input.signal[src] as f32;
                out.reflectivity[dst] = input.reflectivity[src] as f32;
                out.near_ir[dst] = input.raw.near_ir[src] as f32;
                let range = input.range[src];
                if let Some([x, y, z]) = self.lut.point_f32(r0 + rb, m, range) {
                    out.range[dst] = range as f32 * 1e-3;
                    out.points[dst] = Point3::new(x, y, z);
                    out.valid[dst] = valid_col;
                }
            }
        }
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
