//! Robust point-to-point residuals of matched keypoints: the current frame's keypoint point
//! (placed by the pose estimate) against the previous frame's (placed by the previous pose).

use keylo_core::FrameKeypoints;
use nalgebra::{Isometry3, Matrix6, Point3, Vector3, Vector6};

use super::matching::match_rows;
use crate::se3;

/// Matched keypoints of one frame against the previous one.
#[derive(Debug, Clone, Default)]
pub struct Correspondences {
    /// Current keypoint points, sensor frame (deskewed).
    pub source: Vec<Point3<f64>>,
    /// The matched previous keypoint points, world frame.
    pub target: Vec<Point3<f64>>,
}

impl PreviousKeypoints {
    /// `frame` (sensor frame) placed at `pose`.
    pub fn placed(mut frame: FrameKeypoints, pose: &Isometry3<f64>) -> Self {
        for image in &mut frame.per_image {
            for p in &mut image.points {
                *p = pose * *p;
            }
        }
        Self { frame }
    }
}

impl Correspondences {
    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.source.len()
    }

    /// True without pairs.
    pub fn is_empty(&self) -> bool {
        self.source.is_empty()
    }
}

/// A frame's keypoints kept for the next: points in the world frame, per image.
#[derive(Debug, Clone, Default)]
pub struct PreviousKeypoints {
    pub(crate) frame: FrameKeypoints,
}

/// Matching rules.
#[derive(Debug, Clone, Copy)]
pub struct MatchRules {
    pub ratio: f64,
    pub cross_check: bool,
    /// Pairs farther apart than this at the initial guess are dropped (m).
    pub max_distance: f64,
    /// Current points outside `(min, max)` range are dropped (m), as the cloud's.
    pub range: (f64, f64),
}

/// Pairs of `current` (sensor frame, deskewed) with `previous` (world frame) of the same
/// image, kept when they are closer than `rules.max_distance` at `guess`.
pub fn correspond(
    current: &FrameKeypoints,
    previous: &PreviousKeypoints,
    guess: &Isometry3<f64>,
    rules: &MatchRules,
) -> Correspondences {
    let mut out = Correspondences::default();
    for cur in &current.per_image {
        let Some(prev) = previous
            .frame
            .per_image
            .iter()
            .find(|p| p.image == cur.image)
        else {
            continue;
        };
        for (i, j) in match_rows(
            &cur.descriptors,
            &prev.descriptors,
            rules.ratio,
            rules.cross_check,
        ) {
            let (Some(p), Some(q)) = (cur.points.get(i), prev.points.get(j)) else {
                continue;
            };
            let r = p.coords.norm();
            let in_range = r > rules.range.0 && r < rules.range.1;
            if in_range && (guess * p - q).norm() < rules.max_distance {
                out.source.push(*p);
                out.target.push(*q);
            }
        }
    }
    out
}

/// Normal equations of the pairs at `pose` in sensor-centred twist coordinates (`J = [I |
/// −hat(p − c)]`, `c` the sensor position), Geman–McClure weights `κ⁴ / (κ² + r²)²` (1 at
/// r = 0, as the cloud's kernel), with the number of pairs whose weight exceeds ½.
pub fn keypoint_system(
    pairs: &Correspondences,
    pose: &Isometry3<f64>,
    kernel: f64,
) -> (Matrix6<f64>, Vector6<f64>, usize) {
    let (mut h, mut g, mut inliers) = (Matrix6::zeros(), Vector6::zeros(), 0);
    let centre = pose.translation.vector;
    let k2 = kernel * kernel;
    for (p, q) in pairs.source.iter().zip(&pairs.target) {
        let world = pose * p;
        let r: Vector3<f64> = world - q;
        let w = k2 * k2 / (k2 + r.norm_squared()).powi(2);
        let mut j = nalgebra::Matrix3x6::<f64>::zeros();
        j.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
        j.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-se3::hat(&(world.coords - centre))));
        h += j.transpose() * j * w;
        g += j.transpose() * r * w;
        inliers += usize::from(w > 0.5);
    }
    (h, g, inliers)
}
