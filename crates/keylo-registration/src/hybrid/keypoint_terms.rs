//! Robust point-to-point residuals of matched keypoints: the current frame's keypoint point
//! (placed by the pose estimate) against the previous frame's (placed by the previous pose).

use keylo_core::FrameKeypoints;
use nalgebra::{Isometry3, Matrix3, Matrix6, Point3, Vector3, Vector6};

use super::matching::match_rows;
use super::uncertainty::{map_normal, pair_information, point_covariance, PointNoise};
use crate::kiss_icp::voxel_map::VoxelHashMap;
use crate::se3;

/// Matched keypoints of one frame against the previous one.
#[derive(Debug, Clone, Default)]
pub struct Correspondences {
    /// Current keypoint points, sensor frame (deskewed).
    pub source: Vec<Point3<f64>>,
    /// The matched previous keypoint points, world frame.
    pub target: Vec<Point3<f64>>,
    /// Information of each pair (world frame; identity without a noise model).
    pub information: Vec<Matrix3<f64>>,
}

impl PreviousKeypoints {
    /// `frame` (sensor frame) placed at `pose`, with each point's covariance against `map`
    /// (the map that already holds this frame) when `noise` is given.
    pub fn placed(
        mut frame: FrameKeypoints,
        pose: &Isometry3<f64>,
        map: &VoxelHashMap,
        noise: Option<&PointNoise>,
    ) -> Self {
        let mut near = Vec::new();
        let covariances = frame
            .per_image
            .iter_mut()
            .map(|image| {
                image
                    .points
                    .iter_mut()
                    .map(|p| {
                        *p = pose * *p;
                        let noise = noise?;
                        let n = map_normal(map, p, &mut near);
                        Some(point_covariance(p, &pose.translation.vector, n, noise))
                    })
                    .collect()
            })
            .collect();
        Self { frame, covariances }
    }
}

impl PreviousKeypoints {
    fn covariance(&self, image: usize, point: usize) -> Option<Matrix3<f64>> {
        *self.covariances.get(image)?.get(point)?
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
    /// Per image and point: the world-frame covariance (`None` without a noise model).
    covariances: Vec<Vec<Option<Matrix3<f64>>>>,
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
    /// Weigh each pair by its points' covariances; `None`: every pair alike.
    pub noise: Option<PointNoise>,
}

/// Pairs of `current` (sensor frame, deskewed) with `previous` (world frame) of the same
/// image, kept when they are closer than `rules.max_distance` at `guess`; with a noise model,
/// the current points' covariances at `guess` use the surface normals of `map`.
pub fn correspond(
    current: &FrameKeypoints,
    previous: &PreviousKeypoints,
    guess: &Isometry3<f64>,
    map: &VoxelHashMap,
    rules: &MatchRules,
) -> Correspondences {
    let mut out = Correspondences::default();
    let mut near = Vec::new();
    for cur in &current.per_image {
        let Some((k, prev)) = previous
            .frame
            .per_image
            .iter()
            .enumerate()
            .find(|(_, p)| p.image == cur.image)
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
            let world = guess * p;
            let in_range = r > rules.range.0 && r < rules.range.1;
            if !in_range || (world - q).norm() >= rules.max_distance {
                continue;
            }
            let information = match (&rules.noise, previous.covariance(k, j)) {
                (Some(noise), Some(prev_cov)) => {
                    let n = map_normal(map, &world, &mut near);
                    let cov = point_covariance(&world, &guess.translation.vector, n, noise);
                    let Some(info) = pair_information(&cov, &prev_cov) else {
                        continue;
                    };
                    info
                }
                _ => Matrix3::identity(),
            };
            out.source.push(*p);
            out.target.push(*q);
            out.information.push(information);
        }
    }
    out
}

/// Normal equations of the pairs at `pose` in sensor-centred twist coordinates (`J = [I |
/// −hat(p − c)]`, `c` the sensor position), each pair's information `Ω` times a
/// Geman–McClure weight `κ⁴ / (κ² + r²)²` (1 at r = 0, as the cloud's kernel), with the
/// number of pairs whose weight exceeds ½.
pub fn keypoint_system(
    pairs: &Correspondences,
    pose: &Isometry3<f64>,
    kernel: f64,
) -> (Matrix6<f64>, Vector6<f64>, usize) {
    let (mut h, mut g, mut inliers) = (Matrix6::zeros(), Vector6::zeros(), 0);
    let centre = pose.translation.vector;
    let k2 = kernel * kernel;
    for ((p, q), info) in pairs
        .source
        .iter()
        .zip(&pairs.target)
        .zip(&pairs.information)
    {
        let world = pose * p;
        let r: Vector3<f64> = world - q;
        let w = k2 * k2 / (k2 + r.norm_squared()).powi(2);
        let mut j = nalgebra::Matrix3x6::<f64>::zeros();
        j.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
        j.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-se3::hat(&(world.coords - centre))));
        h += j.transpose() * info * j * w;
        g += j.transpose() * info * r * w;
        inliers += usize::from(w > 0.5);
    }
    (h, g, inliers)
}
