//! Unorganised point clouds, the input of a [`crate::Registrar`].

use nalgebra::{Isometry3, Point3};

/// An unorganised cloud: xyz plus optional per-point time and intensity.
///
/// Points are in the sensor frame at `timestamp`. `times`, when present, are seconds relative to
/// `timestamp` (one per point) and let a registrar deskew the scan.
///
/// ```
/// use keylo_core::PointCloud;
/// use nalgebra::Point3;
/// let cloud = PointCloud::from_points(0.0, vec![Point3::new(1.0, 2.0, 3.0)]);
/// assert_eq!(cloud.len(), 1);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointCloud {
    /// Acquisition time of the scan start, seconds.
    pub timestamp: f64,
    /// Points in the sensor frame, metres.
    pub points: Vec<Point3<f64>>,
    /// Per-point time relative to `timestamp`, seconds.
    pub times: Option<Vec<f64>>,
    /// Per-point intensity (signal), sensor units.
    pub intensities: Option<Vec<f32>>,
}

impl PointCloud {
    /// A cloud with points only.
    pub fn from_points(timestamp: f64, points: Vec<Point3<f64>>) -> Self {
        Self {
            timestamp,
            points,
            times: None,
            intensities: None,
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True when the cloud holds no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The points at `indices` (in that order; each `< len()`) with their times and
    /// intensities.
    pub fn subset(&self, indices: &[usize]) -> PointCloud {
        PointCloud {
            timestamp: self.timestamp,
            points: indices.iter().map(|&i| self.points[i]).collect(),
            times: self
                .times
                .as_ref()
                .map(|t| indices.iter().map(|&i| t[i]).collect()),
            intensities: self
                .intensities
                .as_ref()
                .map(|v| indices.iter().map(|&i| v[i]).collect()),
        }
    }

    /// Index of the first point with a non-finite coordinate or time, if any.
    pub fn first_non_finite(&self) -> Option<usize> {
        let bad_point = self
            .points
            .iter()
            .position(|p| !p.coords.iter().all(|c| c.is_finite()));
        let bad_time = self
            .times
            .as_ref()
            .and_then(|t| t.iter().position(|v| !v.is_finite()));
        match (bad_point, bad_time) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// The same cloud with every point transformed by `pose`.
    pub fn transformed(&self, pose: &Isometry3<f64>) -> Self {
        Self {
            points: self.points.iter().map(|p| pose * p).collect(),
            ..self.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_non_finite_points_and_times() {
        let mut cloud = PointCloud::from_points(
            0.0,
            vec![Point3::new(0.0, 0.0, 0.0), Point3::new(f64::NAN, 0.0, 0.0)],
        );
        assert_eq!(cloud.first_non_finite(), Some(1));
        cloud.points[1].x = 1.0;
        assert_eq!(cloud.first_non_finite(), None);
        cloud.times = Some(vec![f64::INFINITY, 0.0]);
        assert_eq!(cloud.first_non_finite(), Some(0));
    }
}
