//! SURF's descriptor (Bay et al. 2008, section 4.2): a square window of side 20s around the
//! keypoint, turned to its direction, resampled to 20×20 cells of size s; per cell the Haar
//! responses dx, dy (weighted by a Gaussian, σ = 3.3 cells); per 5×5-cell subregion
//! Σdx, Σdy, Σ|dx|, Σ|dy|: 4×4×4 = 64 values, normalised to unit length.

use opencv::core::{Mat, Size};
use opencv::prelude::*;

use super::haar::round_even;
use super::orientation::gaussian;
use crate::native::input::Plane;
use crate::FeaturesError;

/// Cells per side of the resampled window.
const PATCH: usize = 20;
const SIGMA: f64 = 3.3;
/// Values per subregion: Σdx, Σdy, Σ|dx|, Σ|dy| (extended: each split by the other's sign).
const BASIC: usize = 4;
const EXTENDED: usize = 8;

/// The descriptor of a keypoint; holds the cell weights.
pub(crate) struct Describer {
    weights: Vec<f32>,
}

impl Describer {
    pub fn new() -> Self {
        let g = gaussian(PATCH, SIGMA);
        let weights = (0..PATCH * PATCH)
            .map(|k| g[k / PATCH] * g[k % PATCH])
            .collect();
        Self { weights }
    }

    /// The values (64, or 128 when `extended`) for a keypoint at `(x, y)` of scale `s`,
    /// direction `angle_deg` (`None`: upright, the window not turned), appended to `out`.
    pub fn describe(
        &self,
        image: &Plane,
        (x, y): (f32, f32),
        s: f32,
        angle_deg: Option<f32>,
        extended: bool,
        out: &mut Vec<f32>,
    ) -> Result<(), FeaturesError> {
        let side = (((PATCH + 1) as f32 * s) as usize).max(1);
        let window = match angle_deg {
            Some(a) => turned_window(image, (x, y), side, a),
            None => upright_window(image, (x, y), side),
        };
        let patch = area_resize(&window, side, PATCH + 1)?;
        let n = PATCH + 1;
        let mut dx = [0.0f32; PATCH * PATCH];
        let mut dy = [0.0f32; PATCH * PATCH];
        for i in 0..PATCH {
            for j in 0..PATCH {
                let p = |r: usize, c: usize| i32::from(patch[r * n + c]);
                let w = self.weights[i * PATCH + j];
                dx[i * PATCH + j] =
                    (p(i, j + 1) - p(i, j) + p(i + 1, j + 1) - p(i + 1, j)) as f32 * w;
                dy[i * PATCH + j] =
                    (p(i + 1, j) - p(i, j) + p(i + 1, j + 1) - p(i, j + 1)) as f32 * w;
            }
        }
        let per = if extended { EXTENDED } else { BASIC };
        let mut v = vec![0.0f32; 16 * per];
        let mut square = 0.0f64;
        for (region, sums) in v.chunks_exact_mut(per).enumerate() {
            let (ri, rj) = (region / 4, region % 4);
            for r in ri * 5..ri * 5 + 5 {
                for c in rj * 5..rj * 5 + 5 {
                    let (tx, ty) = (dx[r * PATCH + c], dy[r * PATCH + c]);
                    if !extended {
                        sums[0] += tx;
                        sums[1] += ty;
                        sums[2] += tx.abs();
                        sums[3] += ty.abs();
                        continue;
                    }
                    let k = if ty >= 0.0 { 0 } else { 2 };
                    sums[k] += tx;
                    sums[k + 1] += tx.abs();
                    let k = if tx >= 0.0 { 4 } else { 6 };
                    sums[k] += ty;
                    sums[k + 1] += ty.abs();
                }
            }
            for &e in sums.iter() {
                square += f64::from(e * e);
            }
        }
        let scale = (1.0 / (square.sqrt() + f64::EPSILON)) as f32;
        out.extend(v.iter().map(|e| e * scale));
        Ok(())
    }
}

/// The `side × side` window centred on `(x, y)` and turned by `angle_deg`, bilinearly
/// interpolated inside the image and nearest (clamped) at its edges.
fn turned_window(image: &Plane, (x, y): (f32, f32), side: usize, angle_deg: f32) -> Vec<u8> {
    let dir = angle_deg * (std::f64::consts::PI / 180.0) as f32;
    let (sin, cos) = (-dir.sin(), dir.cos());
    let offset = -((side as f32 - 1.0) / 2.0);
    let mut start_x = x + offset * cos + offset * sin;
    let mut start_y = y - offset * sin + offset * cos;
    let (last_col, last_row) = (image.width - 1, image.height - 1);
    let mut out = vec![0u8; side * side];
    for row in out.chunks_exact_mut(side.max(1)) {
        let (mut px, mut py) = (f64::from(start_x), f64::from(start_y));
        for v in row.iter_mut() {
            let (ix, iy) = (floor(px), floor(py));
            if ix >= 0 && iy >= 0 && (ix as usize) < last_col && (iy as usize) < last_row {
                let (ix, iy) = (ix as usize, iy as usize);
                let a = (px - ix as f64) as f32;
                let b = (py - iy as f64) as f32;
                let p = |dx: usize, dy: usize| f32::from(image.at(ix + dx, iy + dy));
                let value = p(0, 0) * (1.0 - a) * (1.0 - b)
                    + p(1, 0) * a * (1.0 - b)
                    + p(0, 1) * (1.0 - a) * b
                    + p(1, 1) * a * b;
                *v = round_even(value).clamp(0, 255) as u8;
            } else {
                let cx = (px.round_ties_even().max(0.0) as usize).min(last_col);
                let cy = (py.round_ties_even().max(0.0) as usize).min(last_row);
                *v = image.at(cx, cy);
            }
            px += f64::from(cos);
            py -= f64::from(sin);
        }
        start_x += sin;
        start_y += cos;
    }
    out
}

/// `v.floor()` as an integer, without the library call (window coordinates are small).
#[inline]
fn floor(v: f64) -> i64 {
    let t = v as i64;
    t - i64::from((t as f64) > v)
}

/// The `side × side` window centred on `(x, y)`, not turned (the upright descriptor): whole
/// pixels, clamped at the image's edges, sampled column by column from the bottom up as
/// OpenCV's upright SURF does (its window is the 90° one).
fn upright_window(image: &Plane, (x, y): (f32, f32), side: usize) -> Vec<u8> {
    let offset = -((side as f32 - 1.0) / 2.0);
    let start_x = round_even(x + offset);
    let start_y = round_even(y - offset);
    let clamp = |v: i32, last: usize| (v.max(0) as usize).min(last);
    let mut out = vec![0u8; side * side];
    for (i, row) in out.chunks_exact_mut(side).enumerate() {
        let px = clamp(start_x + i as i32, image.width - 1);
        for (j, v) in row.iter_mut().enumerate() {
            *v = image.at(px, clamp(start_y - j as i32, image.height - 1));
        }
    }
    out
}

/// `window` (`side × side`) resized to `n × n` by pixel-area averaging (OpenCV's `INTER_AREA`).
fn area_resize(window: &[u8], side: usize, n: usize) -> Result<Vec<u8>, FeaturesError> {
    let cv = |what: &str, e: opencv::Error| FeaturesError::opencv(format!("SURF {what}"), e);
    let side_i = i32::try_from(side).map_err(|_| FeaturesError::BadInput("SURF window".into()))?;
    let src = Mat::from_slice(window)
        .and_then(|m| m.reshape(1, side_i).and_then(|m| m.try_clone()))
        .map_err(|e| cv("window", e))?;
    let mut dst = Mat::default();
    let size = Size::new(n as i32, n as i32);
    opencv::imgproc::resize(&src, &mut dst, size, 0.0, 0.0, opencv::imgproc::INTER_AREA)
        .map_err(|e| cv("resize", e))?;
    dst.data_bytes()
        .map(<[u8]>::to_vec)
        .map_err(|e| cv("patch", e))
}
