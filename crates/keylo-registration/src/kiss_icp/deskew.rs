//! Motion compensation with per-point times, as upstream: times normalised to `[0, 1]`, each
//! point moved by `exp((s − 1)·ω)` with `ω = log(last frame-to-frame motion)`, so the scan is
//! expressed at its end.

use nalgebra::{Isometry3, Point3};
use rayon::prelude::*;

use crate::se3;

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
    points
        .par_iter_mut()
        .zip(times.par_iter())
        .with_min_len(4096)
        .for_each(|(p, t)| {
            let s = (t - min) / span;
            *p = se3::exp(&(omega * (s - 1.0))) * *p;
        });
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

    #[test]
    fn equal_times_leave_points_alone() {
        let mut pts = vec![Point3::new(1.0, 2.0, 3.0)];
        deskew(&mut pts, &[0.5], &Isometry3::translation(1.0, 0.0, 0.0));
        assert_eq!(pts[0], Point3::new(1.0, 2.0, 3.0));
    }
}
