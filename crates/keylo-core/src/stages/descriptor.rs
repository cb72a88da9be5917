use crate::{CoreError, Descriptors, Image, Keypoint};

/// Computes a descriptor for every keypoint.
///
/// Owns: its extractor state. It may drop keypoints it cannot describe (e.g. too close to the
/// border): `keypoints` is updated in place so that row `i` of the result describes
/// `keypoints[i]`.
pub trait Descriptor: Send {
    /// Descriptors of `keypoints` in `image`.
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError>;
}
