//! keylo's keypoint front end: LiDAR channels to 8-bit images, detectors and descriptors
//! (OpenCV, native BRIEF/FREAK, SuperPoint), matching, and the keypoint-neighbourhood
//! downsampler of the paper.

pub mod budget;
pub mod classic;
pub mod cv;
mod cv_keypoints;
mod error;
pub mod image;
pub mod matching;
pub mod native;
mod native_heap;
pub mod neighbourhood;
#[cfg(feature = "superpoint")]
mod onnx_session;
#[cfg(feature = "superpoint")]
pub mod superpoint;
#[cfg(feature = "superpoint")]
pub mod xfeat;

pub(crate) use error::check;
pub use error::FeaturesError;
pub use native_heap::keep_native_heap;

/// Registers this crate's backends.
pub fn register(registry: &mut keylo_core::Registry) {
    image::register(registry);
    classic::register(registry);
    native::register(registry);
    neighbourhood::register(registry);
    budget::register(registry);
    #[cfg(feature = "superpoint")]
    superpoint::register(registry);
    #[cfg(feature = "superpoint")]
    xfeat::register(registry);
}
