//! Motion compensation with per-point times, as upstream: times normalised to `[0, 1]`, each
//! point moved by `exp((s − 1)·ω)` with `ω = log(last frame-to-frame motion)`, so the scan is
//! expressed at its end.

use nalgebra::{Isometry3, Point3};
use rayon::prelude::*;

use super::time_table::distinct_times;
use crate::se3;

/// Deskew by a table of transforms when a scan has at most one distinct time per this many
/// points (a spinning sensor's columns), else by one exponential per point.
const POINTS_PER_TIME: usize = 16;

/// Deskews `points` in place; a no-op when all times are equal.
pub fn deskew(points: &mut [Point3<f64>], times: &[f64], last_delta: &Isometry3<f64>) {
    deskew_in_span(points, times, time_span(times), last_delta);
}

/// The earliest and latest of `times` (infinite when empty).
pub fn time_span(times: &[f64]) -> (f64, f64) {
    times
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        })
}

/// [`deskew`] with the scan's time span given: for a subset of a scan (its keypoints), which
/// must be corrected as the whole scan is, not stretched over its own span.
pub fn deskew_in_span(
    points: &mut [Point3<f64>],
    times: &[f64],
    (min, max): (f64, f64),
    last_delta: &Isometry3<f64>,
) {
    let span = max - min;
    if span.is_nan() || span <= 0.0 || points.len() != times.len() {
        return;
    }
    let omega = se3::log(last_delta);
    let motion = |t: f64| se3::exp(&(omega * ((t - min) / span - 1.0)));
    // The same time gives the same transform, so the table changes no bit of the result.
    if let Some((values, index)) = distinct_times(times, points.len() / POINTS_PER_TIME) {
        let motions: Vec<Isometry3<f64>> = values
            .par_iter()
            .with_min_len(256)
            .map(|&t| motion(t))
            .collect();
        points
            .par_iter_mut()
            .zip(index.par_iter())
            .with_min_len(4096)
            .for_each(|(p, &i)| *p = motions[i as usize] * *p);
        return;
    }
    points
        .par_iter_mut()
        .zip(times.par_iter())
        .with_min_len(4096)
        .for_each(|(p, &t)| *p = motion(t) * *p);
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    #[test]
    fn a_static_point_seen_while_moving_is_recovered() {
        // The sensor moves +1 m in x over the scan; a world point at x = 10 is seen at
        // x = 10 − s (s in [0, 1]). Expressed at the scan end (sensor at x = 1) it is x = 9.
        let delta =
            Isometry3::from_parts(Translation3::new(1.0, 0.0, 0.0), UnitQuaternion::identity());
        let times: Vec<f64> = (0..11).map(|i| f64::from(i) * 0.01).collect();
        let mut pts: Vec<_> = times
            .iter()
            .map(|t| Point3::new(10.0 - t * 10.0, 0.0, 0.0))
            .collect();
        deskew(&mut pts, &times, &delta);
        for p in &pts {
            assert!(
                (p.coords - Vector3::new(9.0, 0.0, 0.0)).norm() < 1e-9,
                "{p}"
            );
        }
    }

    /// Column times repeated over rows take the table; per-point times do not. Either way the
    /// points are those of one exponential per point, bit for bit.
    #[test]
    fn the_table_of_column_times_changes_no_bit() {
        let delta = Isometry3::from_parts(
            Translation3::new(0.8, -0.1, 0.02),
            UnitQuaternion::from_euler_angles(0.01, -0.02, 0.05),
        );
        let omega = se3::log(&delta);
        for columns in [64usize, 4096] {
            let times: Vec<f64> = (0..4096)
                .map(|i| 1.7e9 + (i % columns) as f64 * 0.1 / columns as f64)
                .collect();
            let pts: Vec<Point3<f64>> = (0..4096)
                .map(|i| {
                    let a = f64::from(i) * 0.37;
                    Point3::new(5.0 * a.cos(), 5.0 * a.sin(), f64::from(i % 7) - 3.0)
                })
                .collect();
            let (min, max) = time_span(&times);
            let expected: Vec<Point3<f64>> = pts
                .iter()
                .zip(&times)
                .map(|(p, t)| se3::exp(&(omega * ((t - min) / (max - min) - 1.0))) * p)
                .collect();
            let mut got = pts.clone();
            deskew(&mut got, &times, &delta);
            assert_eq!(got, expected, "{columns} columns");
        }
    }

    #[test]
    fn equal_times_leave_points_alone() {
        let mut pts = vec![Point3::new(1.0, 2.0, 3.0)];
        deskew(&mut pts, &[0.5], &Isometry3::translation(1.0, 0.0, 0.0));
        assert_eq!(pts[0], Point3::new(1.0, 2.0, 3.0));
    }
}
