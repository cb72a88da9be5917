//! Beam geometry of organised clouds: the sensor's, from Ouster metadata recorded in the file,
//! or estimated from the first cloud (mean elevation of each row).

use keylo_core::BeamGeometry;

use crate::cloud::RawCloud;
use crate::ouster::OusterMetadata;

/// The geometry of an Ouster sensor's metadata.
pub(crate) fn from_metadata(m: &OusterMetadata) -> BeamGeometry {
    BeamGeometry {
        model: if m.prod_line.is_empty() {
            "Ouster".into()
        } else {
            m.prod_line.clone()
        },
        altitude_deg: m.beam_altitude_angles.clone(),
        azimuth_deg: m.beam_azimuth_angles.clone(),
        origin_to_beam_mm: m.lidar_origin_to_beam_origin_mm,
        columns_per_frame: m.columns_per_frame,
        frame_rate_hz: f64::from(m.fps),
        column_lag_by_row: Vec::new(),
    }
}

/// The geometry seen in `cloud` (organised `rows × cols`): each row's altitude is the mean
/// elevation of its valid points (rows without one are interpolated); azimuth offsets are 0
/// and the frame rate unknown (0).
pub(crate) fn estimate(cloud: &RawCloud, rows: usize, cols: usize, model: &str) -> BeamGeometry {
    let mut sums = vec![(0.0f64, 0usize); rows];
    for (i, p) in cloud.points.iter().enumerate().take(rows * cols) {
        let [x, y, z] = p.map(f64::from);
        let norm = (x * x + y * y + z * z).sqrt();
        if norm.is_finite() && norm > 0.0 {
            let s = &mut sums[i / cols.max(1)];
            s.0 += (z / norm).asin().to_degrees();
            s.1 += 1;
        }
    }
    let known: Vec<(usize, f64)> = sums
        .iter()
        .enumerate()
        .filter(|(_, s)| s.1 > 0)
        .map(|(r, s)| (r, s.0 / s.1 as f64))
        .collect();
    BeamGeometry {
        model: model.to_string(),
        altitude_deg: (0..rows).map(|r| interpolate(&known, r)).collect(),
        azimuth_deg: vec![0.0; rows],
        origin_to_beam_mm: 0.0,
        columns_per_frame: cols,
        frame_rate_hz: 0.0,
        column_lag_by_row: Vec::new(),
    }
}

/// Linear interpolation over `(row, value)` samples sorted by row, constant past the ends.
fn interpolate(known: &[(usize, f64)], r: usize) -> f64 {
    let after = known.partition_point(|&(k, _)| k < r);
    match (after.checked_sub(1).map(|i| known[i]), known.get(after)) {
        (_, Some(&(k, v))) if k == r => v,
        (Some((a, va)), Some(&(b, vb))) => va + (vb - va) * (r - a) as f64 / (b - a) as f64,
        (Some((_, v)), None) | (None, Some(&(_, v))) => v,
        (None, None) => 0.0,
    }
}

/// Whether an organised cloud is staggered (every column one firing time, as older ouster-ros
/// publishes): true when at least 95 % of the columns have all their point times within 1 µs.
/// `None` without point times.
pub(crate) fn is_staggered(cloud: &RawCloud, rows: usize, cols: usize) -> Option<bool> {
    let times = cloud.time.as_ref()?;
    let mut same = 0usize;
    let mut checked = 0usize;
    for c in 0..cols {
        let column = (0..rows).filter_map(|r| times.get(r * cols + c).copied());
        let (lo, hi) = column
            .filter(|t| t.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
                (a.min(t), b.max(t))
            });
        if lo.is_finite() {
            checked += 1;
            same += usize::from(hi - lo <= 1e-6);
        }
    }
    (checked > 0).then(|| same * 100 >= checked * 95)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_get_their_mean_elevation() {
        let s = 45f32.to_radians().sin() * 2.0;
        let c = 45f32.to_radians().cos() * 2.0;
        let cloud = RawCloud {
            points: vec![
                [c, 0.0, s],
                [0.0, c, s],
                [0.0; 3],
                [0.0; 3],
                [2.0, 0.0, 0.0],
                [0.0; 3],
            ],
            ..RawCloud::default()
        };
        let b = estimate(&cloud, 3, 2, "m");
        assert!(
            (b.altitude_deg[0] - 45.0).abs() < 1e-4,
            "{:?}",
            b.altitude_deg
        );
        assert!((b.altitude_deg[1] - 22.5).abs() < 1e-4);
        assert!(b.altitude_deg[2].abs() < 1e-6);
        assert_eq!((b.columns_per_frame, b.azimuth_deg.len()), (2, 3));
    }

    #[test]
    fn staggering_is_told_by_column_times() {
        let staggered = RawCloud {
            time: Some(vec![0.0, 0.1, 0.0, 0.1]),
            ..RawCloud::default()
        };
        assert_eq!(is_staggered(&staggered, 2, 2), Some(true));
        let destaggered = RawCloud {
            time: Some(vec![0.0, 0.1, 0.1, 0.0]),
            ..RawCloud::default()
        };
        assert_eq!(is_staggered(&destaggered, 2, 2), Some(false));
        assert_eq!(is_staggered(&RawCloud::default(), 2, 2), None);
    }
}
