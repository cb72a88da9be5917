//! What one frame pushed into a [`crate::Frontend`] gives back.

use keylo_core::{ChannelFeatures, Degeneracy, FrameFeatures, FrameResult, Keypoint, Pose};
use nalgebra::Point3;

/// The result of one frame: pose, statistics, degeneracy, and the keypoints and descriptors
/// of every image with the 3-D point under each keypoint.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameOutput {
    /// Pose, iterations, point counts, timings, degeneracy.
    pub result: FrameResult,
    /// Per image: the image, its keypoints and their descriptors (row `j` describes keypoint
    /// `j`); empty when the pipeline has no image builder.
    pub features: FrameFeatures,
    /// `keypoint_points[i][j]`: the sensor-frame point under keypoint `j` of image `i`,
    /// `None` when no return lies under it ([`keylo_core::keypoint_points`]).
    pub keypoint_points: Vec<Vec<Option<Point3<f64>>>>,
    /// The frame's pose covariance under the noise model fitted for the registrar (world
    /// frame, twist `[tx, ty, tz, rx, ry, rz]`): what the pose graph and `keylo ros2` use
    /// (docs/maps.md); `None` without a degeneracy analysis.
    pub fitted_covariance: Option<[[f64; 6]; 6]>,
}

/// One keypoint of a [`FrameOutput`] with everything known about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeypointView<'a> {
    /// The image it was found in.
    pub image: &'a ChannelFeatures,
    /// Its index in the image's keypoints (and descriptor row).
    pub index: usize,
    pub keypoint: &'a Keypoint,
    /// Sensor-frame point under it.
    pub point: Option<Point3<f64>>,
}

impl KeypointView<'_> {
    /// Its descriptor: a byte row (binary) or a float row, `None` without descriptors.
    pub fn descriptor(&self) -> Option<DescriptorRow<'_>> {
        let d = self.image.descriptors.as_ref()?;
        let range = self.index * d.dim..(self.index + 1) * d.dim;
        match &d.data {
            keylo_core::DescriptorData::Binary(v) => v.get(range).map(DescriptorRow::Binary),
            keylo_core::DescriptorData::Float(v) => v.get(range).map(DescriptorRow::Float),
        }
    }
}

/// One descriptor row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DescriptorRow<'a> {
    Binary(&'a [u8]),
    Float(&'a [f32]),
}

impl FrameOutput {
    /// The sensor pose in the world (first frame's) frame.
    pub fn pose(&self) -> &Pose {
        &self.result.pose
    }

    /// The registrar's degeneracy analysis, when it makes one.
    pub fn degeneracy(&self) -> Option<&Degeneracy> {
        self.result.degeneracy.as_ref()
    }

    /// The pose covariance for residual noise `sigma` metres ([`Degeneracy::covariance`]);
    /// `None` without a degeneracy analysis or when a direction is unconstrained.
    pub fn covariance(&self, sigma: f64) -> Option<[[f64; 6]; 6]> {
        self.degeneracy()?.covariance(sigma)
    }

    /// Every keypoint of every image, with its descriptor and 3-D point.
    pub fn keypoints(&self) -> impl Iterator<Item = KeypointView<'_>> {
        self.features
            .per_image
            .iter()
            .zip(&self.keypoint_points)
            .flat_map(|(image, points)| {
                image.keypoints.iter().zip(points).enumerate().map(
                    move |(index, (keypoint, point))| KeypointView {
                        image,
                        index,
                        keypoint,
                        point: *point,
                    },
                )
            })
    }
}
