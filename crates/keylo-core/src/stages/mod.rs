//! The stage traits. Each is object safe and `Send`, and exchanges only plain data
//! ([`crate::LidarFrame`], [`crate::Image`], [`crate::Keypoint`], [`crate::PointCloud`]), so a
//! C-ABI plugin can implement any of them over plain buffers.

mod descriptor;
mod detector;
mod downsampler;
mod image_builder;
mod registrar;
mod source;

pub use descriptor::Descriptor;
pub use detector::Detector;
pub use downsampler::Downsampler;
pub use image_builder::ImageBuilder;
pub use registrar::{MapFit, Registrar, Registration};
pub use source::{ImageSource, SourceInfo};
