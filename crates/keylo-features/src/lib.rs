//! keylo's keypoint front end: LiDAR channels to 8-bit images, detectors and descriptors
//! (OpenCV, native BRIEF/FREAK, SuperPoint), matching, and the keypoint-neighbourhood
//! downsampler of the paper.

pub mod cv;
mod error;

pub use error::FeaturesError;
#[allow(unused_imports)]
pub(crate) use error::check;

/// Registers this crate's backends.
pub fn register(_registry: &mut keylo_core::Registry) {}
