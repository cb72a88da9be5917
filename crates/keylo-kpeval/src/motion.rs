//! How a sequence of LiDAR images moves: between each two consecutive images, how far the
//! view turned (the horizontal shift) and how much changed beyond that turn — the two numbers
//! that the match metrics depend on, and that a simulated motion is matched on.

use keylo_core::{Channel, Image};
use keylo_features::cv::to_mat;
use keylo_features::FeaturesError;
use opencv::core::{Mat, Point2d, CV_32F};
use opencv::prelude::*;
use serde::Serialize;

use crate::{ImageSpec, KpEvalError, Plane};

/// Rows left out at the top and at the bottom of the change: a shift moves rows in there
/// from outside the image.
const EDGE_ROWS: usize = 4;

/// How one image follows the one before it (both resized as the study resizes them).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Step {
    /// Horizontal shift, pixels, absolute (phase correlation): how far the view turned.
    pub shift: f64,
    /// Mean absolute difference, grey levels, between the image and the one before it moved by
    /// the shift found (horizontally and vertically, columns wrapping around), over every row
    /// but the first and last four: what changed beyond a turn — parallax as the sensor
    /// travels, tilts, things that move, and the noise of two readings (a still sensor's
    /// change is its noise alone).
    pub change: f64,
}

/// Each consecutive pair of `planes`' signal images, resized as `image` says.
pub fn steps(planes: &[Plane], image: &ImageSpec) -> Result<Vec<Step>, KpEvalError> {
    let mut steps = Vec::new();
    let mut previous: Option<(Image, Mat)> = None;
    for p in planes {
        let img: Image = p.image(
            image.width,
            image.height,
            image.interpolation,
            Channel::Signal,
        )?;
        let mut f = Mat::default();
        to_mat(&img)?
            .convert_to(&mut f, CV_32F, 1.0, 0.0)
            .map_err(|e| FeaturesError::opencv("convert_to", e))?;
        if let Some((prev_img, prev)) = &previous {
            let s = opencv::imgproc::phase_correlate(prev, &f, &opencv::core::no_array(), None)
                .map_err(|e| FeaturesError::opencv("phase_correlate", e))?;
            steps.push(Step {
                shift: s.x.abs(),
                change: change(prev_img, &img, s),
            });
        }
        previous = Some((img, f));
    }
    Ok(steps)
}

/// Mean |b − a moved by `by`| (bilinear, columns wrapping, rows clamped) over the rows
/// [`EDGE_ROWS`] from either edge; 0 for images too small or of different sizes.
fn change(a: &Image, b: &Image, by: Point2d) -> f64 {
    let (w, h) = (a.width, a.height);
    if w == 0 || h <= 2 * EDGE_ROWS || (b.width, b.height) != (w, h) {
        return 0.0;
    }
    let at = |x: isize, y: isize| -> f64 {
        let x = x.rem_euclid(w as isize) as usize;
        let y = y.clamp(0, h as isize - 1) as usize;
        a.get(x, y).map_or(0.0, f64::from)
    };
    // b(x, y) ≈ a(x − dx, y − dy).
    let (fx, fy) = (-by.x, -by.y);
    let (ix, iy) = (fx.floor(), fy.floor());
    let (tx, ty) = (fx - ix, fy - iy);
    let (ix, iy) = (ix as isize, iy as isize);
    let (mut sum, mut n) = (0.0, 0usize);
    for y in EDGE_ROWS..h - EDGE_ROWS {
        for x in 0..w {
            let (sx, sy) = (x as isize + ix, y as isize + iy);
            let top = at(sx, sy) * (1.0 - tx) + at(sx + 1, sy) * tx;
            let bottom = at(sx, sy + 1) * (1.0 - tx) + at(sx + 1, sy + 1) * tx;
            let moved = top * (1.0 - ty) + bottom * ty;
            let v = b.get(x, y).map_or(0.0, f64::from);
            sum += (v - moved).abs();
            n += 1;
        }
    }
    sum / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: usize, h: usize, f: impl Fn(usize, usize) -> u8) -> Image {
        let mut img = Image::new_gray(w, h, Channel::Signal);
        img.data = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        img
    }

    #[test]
    fn a_turn_changes_nothing_beyond_its_shift() {
        let texture = |x: usize, y: usize| ((x * 37 + y * 11) % 97 * 2) as u8;
        let a = image(64, 16, texture);
        let b = image(64, 16, |x, y| texture((x + 64 - 3) % 64, y));
        assert!(change(&a, &b, Point2d::new(3.0, 0.0)) < 1e-9);
        assert!(change(&a, &b, Point2d::new(0.0, 0.0)) > 10.0);
        assert_eq!(
            change(&a, &image(32, 16, texture), Point2d::new(0.0, 0.0)),
            0.0
        );
    }

    #[test]
    fn the_change_of_two_readings_is_their_mean_difference() {
        let a = image(32, 16, |_, _| 100);
        let b = image(32, 16, |x, _| if x % 2 == 0 { 104 } else { 96 });
        assert!((change(&a, &b, Point2d::new(0.0, 0.0)) - 4.0).abs() < 1e-9);
    }
}
