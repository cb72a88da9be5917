//! SURF's orientation (Bay et al. 2008, section 4.1): Haar responses of size 4s at the points
//! of a disc of radius 6s, weighted by a Gaussian (σ = 2.5 samples), summed in a sliding
//! 60° window stepped by 5°; the longest sum gives the direction.

use super::haar::{apply, round_even, scale, BaseBox, ScaledBox};
use crate::native::Integral;

/// Disc radius and window, in samples and degrees.
const RADIUS: i32 = 6;
const WINDOW_DEG: i32 = 60;
const SEARCH_STEP_DEG: usize = 5;
const SIGMA: f64 = 2.5;

/// First-derivative filters on a 4×4 grid: x (left half -1, right +1), y (top +1, bottom -1).
const DX: [BaseBox; 2] = [[0, 0, 2, 4, -1], [2, 0, 4, 4, 1]];
const DY: [BaseBox; 2] = [[0, 0, 4, 2, 1], [0, 2, 4, 4, -1]];

/// The sample points of the disc (x offset outer, y inner) and their Gaussian weights.
pub(crate) struct Disc {
    points: Vec<(i32, i32, f32)>,
}

/// OpenCV's single-precision Gaussian kernel of `n` taps (normalised to sum 1).
pub(crate) fn gaussian(n: usize, sigma: f64) -> Vec<f32> {
    let scale2 = -0.5 / (sigma * sigma);
    let raw: Vec<f32> = (0..n)
        .map(|i| {
            let x = i as f64 - (n as f64 - 1.0) * 0.5;
            (scale2 * x * x).exp() as f32
        })
        .collect();
    let sum = 1.0 / raw.iter().map(|&v| f64::from(v)).sum::<f64>();
    raw.iter().map(|&v| (f64::from(v) * sum) as f32).collect()
}

impl Disc {
    pub fn new() -> Self {
        let g = gaussian((2 * RADIUS + 1) as usize, SIGMA);
        let mut points = Vec::new();
        for i in -RADIUS..=RADIUS {
            for j in -RADIUS..=RADIUS {
                if i * i + j * j <= RADIUS * RADIUS {
                    points.push((i, j, g[(i + RADIUS) as usize] * g[(j + RADIUS) as usize]));
                }
            }
        }
        Self { points }
    }

    /// The direction (degrees, OpenCV's convention: 0–360, y down) of a keypoint at `(x, y)` of
    /// scale `s` (= size · 1.2 / 9), with Haar wavelets of side `wavelet` (2·round(2s), at
    /// most the image's size); `None` when no sample fits in the image.
    pub fn direction(
        &self,
        sat: &Integral,
        (x, y): (f32, f32),
        s: f32,
        wavelet: i32,
    ) -> Option<f32> {
        let stride = sat.stride();
        let (dx, dy): ([ScaledBox; 2], [ScaledBox; 2]) = (
            scale(&DX, 4, wavelet, stride),
            scale(&DY, 4, wavelet, stride),
        );
        let (rows, cols) = (sat.height() as i32 + 1, sat.width() as i32 + 1);
        let half = (wavelet - 1) as f32 / 2.0;
        let mut samples = Vec::with_capacity(self.points.len());
        for &(px, py, w) in &self.points {
            let sx = round_even(x + px as f32 * s - half);
            let sy = round_even(y + py as f32 * s - half);
            if sy < 0 || sy >= rows - wavelet || sx < 0 || sx >= cols - wavelet {
                continue;
            }
            let origin = sy as usize * stride + sx as usize;
            let vx = apply(sat.table(), origin, &dx) * w;
            let vy = apply(sat.table(), origin, &dy) * w;
            samples.push((vx, vy, round_even(fast_atan2(vy, vx))));
        }
        if samples.is_empty() {
            return None;
        }
        let (mut best, mut best_x, mut best_y) = (0.0f32, 0.0f32, 0.0f32);
        for centre in (0..360i32).step_by(SEARCH_STEP_DEG) {
            let (mut sx, mut sy) = (0.0f32, 0.0f32);
            for &(vx, vy, angle) in &samples {
                let d = (angle - centre).abs();
                // Within half the window of the centre, around the circle.
                if !(WINDOW_DEG / 2..=360 - WINDOW_DEG / 2).contains(&d) {
                    sx += vx;
                    sy += vy;
                }
            }
            let m = sx * sx + sy * sy;
            if m > best {
                (best, best_x, best_y) = (m, sx, sy);
            }
        }
        Some(fast_atan2(-best_y, best_x))
    }
}

/// OpenCV's `fastAtan2` (degrees, 0–360; about 0.3° accurate), the angle SURF's windows and
/// keypoints use.
pub(crate) fn fast_atan2(y: f32, x: f32) -> f32 {
    opencv::core::fast_atan2(y, x).unwrap_or(0.0)
}
