use crate::{CoreError, Image, Keypoint};

/// Finds keypoints in an image.
///
/// Owns: its detector state (e.g. an OpenCV object or an ONNX session). Keypoints are in image
/// pixels of the image passed in.
pub trait Detector: Send {
    /// Keypoints of one image.
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError>;
}
