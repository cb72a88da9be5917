//! keylo core: the data types every stage exchanges, the stage traits, the config schema,
//! the registry that maps `kind = "..."` names to constructors, and the [`Pipeline`].
//!
//! The data flow of one frame:
//! `ImageSource` → [`LidarFrame`] → `ImageBuilder` → [`Image`]s → `Detector` → [`Keypoint`]s →
//! `Descriptor` → [`Descriptors`] → `Downsampler` → [`PointCloud`] → `Registrar` → [`Pose`].

pub mod cloud;
pub mod config;
pub mod degeneracy;
pub mod degenerate;
pub mod error;
pub mod features;
pub mod frame;
pub mod image;
pub mod keypoints3d;
pub mod matching;
pub mod pipeline;
pub mod pixel_math;
pub mod registry;
pub mod rigid;
pub mod scan;
pub mod stages;
pub mod trajectory;
pub mod voxel;

pub use cloud::PointCloud;
pub use degeneracy::Degeneracy;
pub use degenerate::Degenerate;
pub use error::{ConfigError, CoreError, ShapeError};
pub use features::{ChannelFeatures, DescriptorData, Descriptors, FrameFeatures, Keypoint};
pub use frame::{BeamGeometry, Channel, LidarFrame};
pub use image::Image;
pub use keypoints3d::{keypoint_points, FrameKeypoints, ImageKeypoints};
pub use pipeline::{
    build_source, FrameResult, Odometry, Paced, PerImage, Pipeline, Prefetched, StageTimings,
};
pub use registry::{BuildContext, Registry};
pub use scan::{GridOccupancy, PixelPoints, ScanPoints};
pub use stages::{
    Descriptor, Detector, Downsampler, ImageBuilder, ImageSource, MapFit, Registrar, Registration,
    SourceInfo,
};
pub use trajectory::{Pose, Trajectory};
