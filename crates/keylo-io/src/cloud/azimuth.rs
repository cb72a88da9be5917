//! A point's image column from its azimuth, without calling `atan2` for most points: a
//! polynomial arctangent (error below 4e-8 rad) gives the column, and only points within
//! 1e-6 rad of a column boundary are decided by `atan2`, so the column is the one `atan2`
//! gives.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Angles closer than this to a column boundary are recomputed with `atan2` (radians; 25×
/// the polynomial's largest error).
const EXACT_NEAR: f64 = 1e-6;

/// Column of azimuth `atan2(y, x)` over `cols` columns: clockwise from +x, column 0 centred
/// on the +x axis (the layout of Ouster's destaggered images).
#[inline]
pub(crate) fn azimuth_column(x: f64, y: f64, cols: usize) -> usize {
    let per_radian = cols as f64 / TAU;
    let approx = clockwise(fast_atan2(y, x)) * per_radian;
    // `approx` is in [0, cols]: truncation is `floor` (which is a libm call on baseline
    // x86-64), and away from a boundary `+ 0.5` then truncation is `round`.
    let whole = approx as usize;
    let from_boundary = (approx - whole as f64 - 0.5).abs() / per_radian;
    let column = if from_boundary > EXACT_NEAR && approx.is_finite() {
        (approx + 0.5) as usize
    } else {
        (clockwise(y.atan2(x)) / TAU * cols as f64).round() as usize
    };
    column % cols
}

/// Clockwise angle in `[0, 2π]` of the counter-clockwise angle `a` in `[-π, π]`.
#[inline]
fn clockwise(a: f64) -> f64 {
    let a = -a;
    if a < 0.0 {
        a + TAU
    } else {
        a
    }
}

/// `atan2(y, x)` to within 4e-8 rad (Abramowitz & Stegun 4.4.49 on `[0, 1]`, then octant
/// reduction).
#[inline]
fn fast_atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    if ax == 0.0 && ay == 0.0 {
        return y.atan2(x);
    }
    let swap = ay > ax;
    let t = if swap { ax / ay } else { ay / ax };
    let mut a = atan_unit(t);
    if swap {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y.is_sign_negative() {
        -a
    } else {
        a
    }
}

/// `atan(t)` for `t` in `[0, 1]`.
#[inline]
fn atan_unit(t: f64) -> f64 {
    const C: [f64; 8] = [
        0.999_999_332_9,
        -0.333_298_560_5,
        0.199_465_359_9,
        -0.139_085_335_1,
        0.096_420_044_1,
        -0.055_909_886_1,
        0.021_861_228_8,
        -0.004_054_058_0,
    ];
    let t2 = t * t;
    let mut p = C[7];
    for c in C[..7].iter().rev() {
        p = p * t2 + c;
    }
    p * t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The column as `atan2` alone gives it.
    fn exact(x: f64, y: f64, cols: usize) -> usize {
        ((clockwise(y.atan2(x)) / TAU * cols as f64).round() as usize) % cols
    }

    #[test]
    fn the_polynomial_is_within_its_bound() {
        let mut worst = 0.0f64;
        for i in 0..=100_000 {
            let a = -PI + TAU * f64::from(i) / 100_000.0;
            let (y, x) = a.sin_cos();
            for r in [1e-3, 1.0, 80.0] {
                worst = worst.max((fast_atan2(r * y, r * x) - (r * y).atan2(r * x)).abs());
            }
        }
        assert!(worst < 4e-8, "{worst}");
    }

    #[test]
    fn columns_equal_atan2_columns_also_at_boundaries() {
        for cols in [512, 1024, 1800, 2048] {
            let step = TAU / cols as f64;
            for c in 0..cols {
                // Exactly on, and a hair either side of, the boundary below column c.
                for d in [0.0, 1e-12, -1e-12, 5e-7, -5e-7, 0.25 * step, 0.5 * step] {
                    let a = -((c as f64 - 0.5) * step + d);
                    let (y, x) = a.sin_cos();
                    for r in [0.5, 37.0] {
                        let (x, y) = (r * x, r * y);
                        assert_eq!(azimuth_column(x, y, cols), exact(x, y, cols), "{x} {y}");
                    }
                }
            }
        }
        assert_eq!(azimuth_column(1.0, 0.0, 8), 0);
        assert_eq!(azimuth_column(0.0, -1.0, 8), 2); // 90° clockwise
        assert_eq!(azimuth_column(-1.0, 0.0, 8), 4);
        assert_eq!(azimuth_column(-1.0, -0.0, 8), 4);
        assert_eq!(azimuth_column(0.0, 1.0, 8), 6);
        assert_eq!(azimuth_column(1.0, 1e-9, 8), 0);
        assert_eq!(azimuth_column(0.0, 0.0, 8), 0);
    }
}
