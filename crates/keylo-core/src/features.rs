//! Keypoints and descriptors, laid out so a C plugin can fill them from plain buffers.

use crate::Image;

/// A keypoint in image pixels, with the fields of OpenCV's `cv::KeyPoint`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Keypoint {
    pub x: f32,
    pub y: f32,
    /// Diameter of the meaningful neighbourhood, pixels.
    pub size: f32,
    /// Orientation in degrees, -1 when not applicable.
    pub angle: f32,
    /// Detector response (strength).
    pub response: f32,
    /// Pyramid octave.
    pub octave: i32,
    /// Detector-specific id (OpenCV's `class_id`; AKAZE keeps its evolution level here, which
    /// its descriptor needs).
    pub class_id: i32,
}

/// Descriptor rows, one per keypoint.
#[derive(Debug, Clone, PartialEq)]
pub enum DescriptorData {
    /// Binary descriptors (compared with Hamming distance), `dim` bytes per row.
    Binary(Vec<u8>),
    /// Float descriptors (compared with L2), `dim` floats per row.
    Float(Vec<f32>),
}

/// A descriptor matrix: `rows` descriptors of `dim` elements each.
#[derive(Debug, Clone, PartialEq)]
pub struct Descriptors {
    pub rows: usize,
    pub dim: usize,
    pub data: DescriptorData,
}

/// Keypoints and descriptors found in one image of a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelFeatures {
    pub image: Image,
    pub keypoints: Vec<Keypoint>,
    pub descriptors: Option<Descriptors>,
}

/// Everything the feature stages found in one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameFeatures {
    pub per_image: Vec<ChannelFeatures>,
}

impl FrameFeatures {
    /// Total keypoints over all images.
    pub fn keypoint_count(&self) -> usize {
        self.per_image.iter().map(|c| c.keypoints.len()).sum()
    }
}
