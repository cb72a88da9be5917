//! How alike two sets of 8-bit LiDAR images look, beside the detectors' metrics: the share of
//! pixels per grey level and per gradient magnitude over each set (images as the detectors
//! see them, resized), and distances between two sets' histograms.

use keylo_core::Channel;
use serde::Serialize;

use crate::{ImageSpec, KpEvalError, Plane};

/// Bins of the gradient-magnitude histogram.
pub const GRADIENT_BINS: usize = 128;
/// Width of a gradient bin, grey levels per pixel of Sobel magnitude (the last bin takes
/// everything from `(GRADIENT_BINS - 1) · width` up to the largest, ≈ 1442).
pub const GRADIENT_BIN_WIDTH: f64 = 8.0;

/// Row bands of the row profile (eighths of the image, top first).
pub const ROW_BANDS: usize = 8;

/// Bins of the residual histograms: |pixel − mean of two neighbours| in half grey levels.
const RESIDUAL_BINS: usize = 511;

/// The mean histograms of a set of images.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Histograms {
    /// Images in the set.
    pub images: usize,
    /// Share of pixels per grey level (256 bins, summing to 1).
    pub intensity: Vec<f64>,
    /// Share of interior pixels per bin of Sobel gradient magnitude ([`GRADIENT_BINS`] bins of
    /// [`GRADIENT_BIN_WIDTH`], summing to 1).
    pub gradient: Vec<f64>,
    /// Mean grey level of each of [`ROW_BANDS`] bands of rows, top first: where the image is
    /// bright (ceiling, walls, floor next to the sensor).
    pub row_profile: Vec<f64>,
    /// Share of interior pixels per |pixel − mean of the pixels above and below|, in bins of
    /// half a grey level: how much rows differ from their neighbours (beam gains, streaks).
    pub row_residual: Vec<f64>,
    /// The same with the pixels left and right.
    pub column_residual: Vec<f64>,
}

impl Histograms {
    /// The histograms of `planes`, each resized as `image` says (size and interpolation).
    pub fn of<'a>(
        planes: impl IntoIterator<Item = &'a Plane>,
        image: &ImageSpec,
    ) -> Result<Self, KpEvalError> {
        let mut intensity = vec![0.0; 256];
        let mut gradient = vec![0.0; GRADIENT_BINS];
        let mut bands = vec![(0.0, 0usize); ROW_BANDS];
        let mut row_residual = vec![0.0; RESIDUAL_BINS];
        let mut column_residual = vec![0.0; RESIDUAL_BINS];
        let mut images = 0;
        for plane in planes {
            images += 1;
            let img = plane.image(
                image.width,
                image.height,
                image.interpolation,
                Channel::Signal,
            )?;
            add_intensity(&img.data, &mut intensity);
            add_gradient(&img.data, img.width, img.height, &mut gradient);
            add_rows(&img.data, img.width, img.height, &mut bands);
            add_residuals(
                &img.data,
                img.width,
                img.height,
                &mut row_residual,
                &mut column_residual,
            );
        }
        normalise(&mut intensity);
        normalise(&mut gradient);
        normalise(&mut row_residual);
        normalise(&mut column_residual);
        Ok(Self {
            images,
            intensity,
            gradient,
            row_profile: bands
                .iter()
                .map(|&(sum, n)| if n > 0 { sum / n as f64 } else { 0.0 })
                .collect(),
            row_residual,
            column_residual,
        })
    }

    /// Median |pixel − mean of the pixels above and below|, grey levels.
    pub fn median_row_residual(&self) -> f64 {
        median_of(&self.row_residual)
    }

    /// Median |pixel − mean of the pixels left and right|, grey levels.
    pub fn median_column_residual(&self) -> f64 {
        median_of(&self.column_residual)
    }

    /// Mean grey level.
    pub fn mean_intensity(&self) -> f64 {
        weighted_sum(&self.intensity, |i| i as f64)
    }

    /// Mean gradient magnitude (of the bins' centres).
    pub fn mean_gradient(&self) -> f64 {
        weighted_sum(&self.gradient, |i| (i as f64 + 0.5) * GRADIENT_BIN_WIDTH)
    }
}

/// How far apart two histograms of the same bins are.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Distance {
    /// Earth mover's (1-Wasserstein) distance, in the bins' unit (grey levels, or grey levels
    /// per pixel of gradient): how far the mass must move, on average, to turn one into the
    /// other.
    pub emd: f64,
    /// Hellinger distance, 0 (same) … 1 (no overlap).
    pub hellinger: f64,
}

/// The distance between histograms `a` and `b` (shares summing to 1) of bins `bin_width` wide.
pub fn distance(a: &[f64], b: &[f64], bin_width: f64) -> Distance {
    let (mut cdf_a, mut cdf_b, mut emd, mut bc) = (0.0, 0.0, 0.0, 0.0);
    for (&x, &y) in a.iter().zip(b) {
        cdf_a += x;
        cdf_b += y;
        emd += (cdf_a - cdf_b).abs() * bin_width;
        bc += (x * y).sqrt();
    }
    Distance {
        emd,
        hellinger: (1.0 - bc.min(1.0)).max(0.0).sqrt(),
    }
}

fn add_intensity(data: &[u8], hist: &mut [f64]) {
    for &v in data {
        hist[usize::from(v)] += 1.0;
    }
}

/// Every pixel's grey level into the (sum, count) of its row band.
fn add_rows(data: &[u8], width: usize, height: usize, bands: &mut [(f64, usize)]) {
    for (y, row) in data.chunks(width.max(1)).take(height).enumerate() {
        let band = &mut bands[(y * ROW_BANDS / height.max(1)).min(ROW_BANDS - 1)];
        band.0 += row.iter().map(|&v| f64::from(v)).sum::<f64>();
        band.1 += row.len();
    }
}

/// Sobel magnitude of every interior pixel into `hist`.
fn add_gradient(data: &[u8], width: usize, height: usize, hist: &mut [f64]) {
    let px = |x: usize, y: usize| f64::from(data[y * width + x]);
    for y in 1..height.saturating_sub(1) {
        for x in 1..width.saturating_sub(1) {
            let gx = (px(x + 1, y - 1) + 2.0 * px(x + 1, y) + px(x + 1, y + 1))
                - (px(x - 1, y - 1) + 2.0 * px(x - 1, y) + px(x - 1, y + 1));
            let gy = (px(x - 1, y + 1) + 2.0 * px(x, y + 1) + px(x + 1, y + 1))
                - (px(x - 1, y - 1) + 2.0 * px(x, y - 1) + px(x + 1, y - 1));
            let bin = (gx.hypot(gy) / GRADIENT_BIN_WIDTH) as usize;
            hist[bin.min(GRADIENT_BINS - 1)] += 1.0;
        }
    }
}

/// |pixel − mean of the pixels above and below| of every pixel that has both into `rows`, and
/// |pixel − mean of the pixels left and right| into `columns`, in half grey levels.
fn add_residuals(data: &[u8], width: usize, height: usize, rows: &mut [f64], columns: &mut [f64]) {
    let px = |x: usize, y: usize| i32::from(data[y * width + x]);
    let add = |hist: &mut [f64], twice: i32| {
        hist[(twice.unsigned_abs() as usize).min(RESIDUAL_BINS - 1)] += 1.0;
    };
    for y in 0..height {
        for x in 0..width {
            let v = 2 * px(x, y);
            if y >= 1 && y + 1 < height {
                add(rows, v - px(x, y - 1) - px(x, y + 1));
            }
            if x >= 1 && x + 1 < width {
                add(columns, v - px(x - 1, y) - px(x + 1, y));
            }
        }
    }
}

/// The median of a histogram in half grey levels (the bin where the share reaches one half).
fn median_of(hist: &[f64]) -> f64 {
    let mut cumulative = 0.0;
    for (bin, share) in hist.iter().enumerate() {
        cumulative += share;
        if cumulative >= 0.5 {
            return 0.5 * bin as f64;
        }
    }
    0.0
}

fn normalise(hist: &mut [f64]) {
    let total: f64 = hist.iter().sum();
    if total > 0.0 {
        hist.iter_mut().for_each(|h| *h /= total);
    }
}

/// `Σ hist[i] · value(i)`.
fn weighted_sum(hist: &[f64], value: impl Fn(usize) -> f64) -> f64 {
    hist.iter().enumerate().map(|(i, h)| h * value(i)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(data: Vec<u8>, rows: usize, cols: usize) -> Plane {
        Plane {
            rows,
            cols,
            data,
            label: "t".into(),
        }
    }

    fn own_size() -> ImageSpec {
        ImageSpec {
            width: 0,
            height: 0,
            ..ImageSpec::default()
        }
    }

    #[test]
    fn flat_image_has_one_grey_level_and_no_gradient() {
        let h = Histograms::of(&[plane(vec![40; 20], 4, 5)], &own_size()).unwrap();
        assert_eq!(h.intensity[40], 1.0);
        assert_eq!(h.gradient[0], 1.0);
        assert_eq!(h.mean_intensity(), 40.0);
        assert_eq!(h.row_profile.len(), ROW_BANDS);
        assert_eq!(h.mean_gradient(), 0.5 * GRADIENT_BIN_WIDTH);
    }

    #[test]
    fn vertical_edge_has_the_sobel_magnitude() {
        // Columns 0..2 are 0, columns 2..4 are 10: interior pixels at x = 1 and 2 see the
        // step, gx = 4 · 10 = 40 → bin 5.
        let row = [0u8, 0, 10, 10];
        let h = Histograms::of(&[plane(row.repeat(3), 3, 4)], &own_size()).unwrap();
        assert_eq!(h.gradient[5], 1.0);
        assert_eq!(h.intensity[0], 0.5);
        assert_eq!(h.intensity[10], 0.5);
        // Three rows into eight bands: rows 0, 1, 2 fill bands 0, 2 and 5 (the rest empty).
        assert_eq!(h.row_profile[0], 5.0);
        assert_eq!(h.row_profile[1], 0.0);
        // Rows are alike; across the edge a pixel is 5 from the mean of its neighbours.
        assert_eq!(h.median_row_residual(), 0.0);
        assert_eq!(h.column_residual[10], 1.0); // |2·0 − 0 − 10| = 10 half levels
        assert_eq!(h.median_column_residual(), 5.0);
    }

    #[test]
    fn striped_rows_have_a_row_residual() {
        // Rows alternate 100 and 120: every interior row is 20 from its neighbours' mean.
        let data: Vec<u8> = (0..5)
            .flat_map(|r| [if r % 2 == 0 { 100 } else { 120 }; 6])
            .collect();
        let h = Histograms::of(&[plane(data, 5, 6)], &own_size()).unwrap();
        assert_eq!(h.median_row_residual(), 20.0);
        assert_eq!(h.median_column_residual(), 0.0);
    }

    #[test]
    fn distances_of_same_shifted_and_disjoint_histograms() {
        let mut a = vec![0.0; 8];
        let mut b = vec![0.0; 8];
        a[2] = 1.0;
        b[5] = 1.0;
        let same = distance(&a, &a, 1.0);
        assert_eq!((same.emd, same.hellinger), (0.0, 0.0));
        let apart = distance(&a, &b, 2.0);
        assert_eq!(apart.emd, 6.0);
        assert_eq!(apart.hellinger, 1.0);
        b[2] = 0.5;
        b[5] = 0.5;
        let half = distance(&a, &b, 1.0);
        assert!((half.emd - 1.5).abs() < 1e-12);
        assert!((half.hellinger - (1.0 - 0.5f64.sqrt()).sqrt()).abs() < 1e-12);
    }
}
