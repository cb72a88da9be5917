use crate::{CoreError, Descriptors, Image, Keypoint};

/// Finds keypoints in an image.
///
/// Owns: its detector state (e.g. an OpenCV object or an ONNX session). Keypoints are in image
/// pixels of the image passed in.
pub trait Detector: Send {
    /// Keypoints of one image.
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError>;

    /// Keypoints and, for detectors that compute them in the same pass (SuperPoint, AKAZE),
    /// their descriptors, row `i` describing keypoint `i`. The pipeline keeps these
    /// descriptors when no `[descriptor]` stage is configured. By default: [`Self::detect`]
    /// and no descriptors.
    fn detect_and_describe(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), CoreError> {
        Ok((self.detect(image)?, None))
    }
}
