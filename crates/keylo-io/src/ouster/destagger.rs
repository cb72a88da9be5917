//! Staggered packet columns → the destaggered, organised [`LidarFrame`]: every channel
//! shifted row by row as ouster-sdk's `destagger` does, XYZ from the beam and encoder terms,
//! and the firing time of every pixel.

use std::mem::MaybeUninit;
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
}

/// One block of destaggered rows of every output grid, spare capacity the destagger writes
/// every element of once before the vectors take it as their length.
struct RowOut<'a> {
    range: &'a mut [MaybeUninit<f32>],
    signal: &'a mut [MaybeUninit<f32>],
    reflectivity: &'a mut [MaybeUninit<f32>],
    near_ir: &'a mut [MaybeUninit<f32>],
    points: &'a mut [MaybeUninit<Point3<f32>>],
    valid: &'a mut [MaybeUninit<bool>],
}

/// An empty vector with room for `n` values, allocated zeroed: measured faster than an
/// uninitialised allocation here (mimalloc hands fresh, already zero pages to a zeroed
/// allocation of this size without a memset).
fn zeroed<T: Clone + Default>(n: usize) -> Vec<T> {
    let mut v = vec![T::default(); n];
    v.clear();
    v
}

/// The output grids of one frame, allocated and not yet written.
struct Grids {
    range: Vec<f32>,
    signal: Vec<f32>,
    reflectivity: Vec<f32>,
    near_ir: Vec<f32>,
    points: Vec<Point3<f32>>,
    valid: Vec<bool>,
}

impl Grids {
    fn with_capacity(n: usize) -> Self {
        Self {
            range: zeroed(n),
            signal: zeroed(n),
            reflectivity: zeroed(n),
            near_ir: zeroed(n),
            points: Vec::with_capacity(n),
            valid: zeroed(n),
        }
    }

    /// Marks the first `n` elements of every grid written.
    ///
    /// # Safety
    /// Every grid must have its first `n` elements written.
    unsafe fn set_len(&mut self, n: usize) {
        // SAFETY: the caller wrote the first `n` elements, within the capacity.
        unsafe {
            self.range.set_len(n);
            self.signal.set_len(n);
            self.reflectivity.set_len(n);
            self.near_ir.set_len(n);
            self.points.set_len(n);
            self.valid.set_len(n);
        }
    }
}

/// Rows destaggered together (16 u32 values = one cache line of a staggered column).
const ROW_BLOCK: usize = 16;

/// Staggered columns destaggered together: a tile of `ROW_BLOCK` rows × `COL_TILE` columns
/// reads whole cache lines of the inputs and writes runs of a row, all within L1.
const COL_TILE: usize = 64;

/// One tile of the staggered channels in row order: `[row in block][column in tile]`.
struct Tile {
    range: [[u32; COL_TILE]; ROW_BLOCK],
    signal: [[u32; COL_TILE]; ROW_BLOCK],
    reflectivity: [[u32; COL_TILE]; ROW_BLOCK],
    near_ir: [[u32; COL_TILE]; ROW_BLOCK],
}

impl Tile {
    fn new() -> Self {
        let zero = [[0; COL_TILE]; ROW_BLOCK];
        Self {
            range: zero,
            signal: zero,
            reflectivity: zero,
            near_ir: zero,
        }
    }
}

/// Copies `rows` values from each staggered column starting at the offsets `columns` into
/// the tile's columns: `tile[row][k] = src[columns[k] + row]`.
fn transpose(
    src: &[u32],
    columns: impl Iterator<Item = usize>,
    rows: usize,
    tile: &mut [[u32; COL_TILE]; ROW_BLOCK],
) {
    for (k, start) in columns.enumerate() {
        for (row, &v) in tile.iter_mut().zip(&src[start..start + rows]) {
            row[k] = v;
        }
    }
}

/// `out[i] = f(src[i])` over the shorter of the two.
#[inline]
fn write_each<S, T>(out: &mut [MaybeUninit<T>], src: &[S], f: impl Fn(&S) -> T) {
    for (o, v) in out.iter_mut().zip(src) {
        o.write(f(v));
    }
}

/// A run of one row: `len` staggered columns from `m` (tile column `k`) written at `dst`.
struct Run {
    row: usize,
    m: usize,
    k: usize,
    dst: usize,
    len: usize,
}

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
            // Row `r`'s pixel in column `c` came from staggered column `c − shift(r)`, and
            // `column_times[c]` is staggered column `c − median_shift`'s time.
            column_lag_by_row: shifts
                .iter()
                .map(|s| (s + cols - median_shift) % cols.max(1))
                .collect(),
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
        let n = self.rows * self.cols;
        let mut g = Grids::with_capacity(n);
        let input = Staggered {
            range,
            signal,
            reflectivity,
            raw,
        };
        // Rows are independent: destagger blocks of rows in parallel, each into its own
        // output rows. A block reads the staggered (column-major) buffers a cache line per
        // column instead of one value per cache line.
        let block = ROW_BLOCK * self.cols.max(1);
        g.range.spare_capacity_mut()[..n]
            .par_chunks_mut(block)
            .zip(g.signal.spare_capacity_mut()[..n].par_chunks_mut(block))
            .zip(g.reflectivity.spare_capacity_mut()[..n].par_chunks_mut(block))
            .zip(g.near_ir.spare_capacity_mut()[..n].par_chunks_mut(block))
            .zip(g.points.spare_capacity_mut()[..n].par_chunks_mut(block))
            .zip(g.valid.spare_capacity_mut()[..n].par_chunks_mut(block))
            .enumerate()
            .for_each(|(b, (((((rg, sg), rf), nir), pts), ok))| {
                let out = RowOut {
                    range: rg,
                    signal: sg,
                    reflectivity: rf,
                    near_ir: nir,
                    points: pts,
                    valid: ok,
                };
                self.rows_block(b * ROW_BLOCK, &input, out);
            });
        // SAFETY: the chunks cover all `n` elements, `rows_block` writes every pixel of its
        // rows (per row, staggered column `m` → `(m + shift) mod cols` is a bijection of
        // `0..cols`), and a panic above leaves the vectors empty.
        unsafe { g.set_len(n) };
        let column_times = (0..self.cols)
            .map(|c| staggered_times[(c + self.cols - self.median_shift) % self.cols])
            .collect();
        LidarFrame {
            index,
            timestamp,
            rows: self.rows,
            cols: self.cols,
            column_times,
            // Each pixel's time is its staggered column's: `beams.column_lag_by_row` gives
            // it from `column_times` (`LidarFrame::pixel_time`) without a per-pixel array.
            pixel_times: None,
            range: g.range,
            signal: g.signal,
            reflectivity: g.reflectivity,
            near_ir: g.near_ir,
            points: g.points,
            valid: g.valid,
            beams: Arc::clone(&self.beams),
            scan: None,
        }
    }

    /// Destaggers the rows `r0..` that `out` holds: destaggered column `c` of row `r` is
    /// staggered column `m = c - shift(r)` (mod cols). Tiles of `COL_TILE` staggered columns
    /// are first transposed into row order (reads of the column-major input a cache line per
    /// column), then each row's run is written contiguously.
    fn rows_block(&self, r0: usize, input: &Staggered, mut out: RowOut) {
        let (rows, cols) = (self.rows, self.cols);
        let n = out.range.len() / cols.max(1);
        let shifts = &self.shifts[r0..r0 + n];
        let mut tile = Tile::new();
        for m0 in (0..cols).step_by(COL_TILE) {
            let w = COL_TILE.min(cols - m0);
            // One channel at a time: the four tiles are 4 KiB apart, and stores to all of
            // them in one loop alias in L1.
            let columns = (m0..m0 + w).map(|m| m * rows + r0);
            transpose(input.range, columns.clone(), n, &mut tile.range);
            transpose(input.signal, columns.clone(), n, &mut tile.signal);
            transpose(
                input.reflectivity,
                columns.clone(),
                n,
                &mut tile.reflectivity,
            );
            transpose(&input.raw.near_ir, columns, n, &mut tile.near_ir);
            for (rb, &shift) in shifts.iter().enumerate() {
                // Staggered columns m0.. land at c0..; the run wraps at the last column.
                let c0 = (m0 + shift) % cols;
                let split = (cols - c0).min(w);
                let runs = [(0, c0, split), (split, 0, w - split)];
                for (k0, c, len) in runs.into_iter().filter(|r| r.2 > 0) {
                    let run = Run {
                        row: r0 + rb,
                        m: m0 + k0,
                        k: k0,
                        dst: rb * cols + c,
                        len,
                    };
                    self.write_run(&run, rb, &tile, input, &mut out);
                }
            }
        }
    }

    /// Writes `run.len` pixels of one row from the transposed tile.
    fn write_run(&self, run: &Run, rb: usize, tile: &Tile, input: &Staggered, out: &mut RowOut) {
        let (len, dst) = (run.len, run.dst..run.dst + run.len);
        let (k, m) = (run.k..run.k + len, run.m..run.m + len);
        let beam = self.lut.beam(run.row);
        let src_range = &tile.range[rb][k.clone()];
        let src_signal = &tile.signal[rb][k.clone()];
        let src_refl = &tile.reflectivity[rb][k.clone()];
        let src_nir = &tile.near_ir[rb][k];
        let angles = &self.lut.columns()[m.clone()];
        let col_valid = &input.raw.column_valid[m.clone()];
        let o_range = &mut out.range[dst.clone()];
        let o_signal = &mut out.signal[dst.clone()];
        let o_refl = &mut out.reflectivity[dst.clone()];
        let o_nir = &mut out.near_ir[dst.clone()];
        let o_points = &mut out.points[dst.clone()];
        let o_valid = &mut out.valid[dst.clone()];
        // One simple loop per output (vectorised by the compiler), all within L1.
        write_each(o_signal, src_signal, |&v| v as f32);
        write_each(o_refl, src_refl, |&v| v as f32);
        write_each(o_nir, src_nir, |&v| v as f32);
        write_each(o_range, src_range, |&r| r as f32 * 1e-3);
        for ((o, &ok), &r) in o_valid.iter_mut().zip(col_valid).zip(src_range) {
            o.write(ok && r != 0);
        }
        for ((o, &angle), &r) in o_points.iter_mut().zip(angles).zip(src_range) {
            let [x, y, z] = self.lut.point_of(beam, angle, r);
            o.write(if r != 0 {
                Point3::new(x, y, z)
            } else {
                Point3::origin()
            });
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
