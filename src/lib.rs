//! keylo: keypoint-assisted LiDAR odometry.
//!
//! This facade re-exports the keylo crates and offers [`registry`], the registry with every
//! built-in backend of the enabled features (`opencv`, `superpoint`, `ros`, `sim`,
//! `plugins`; all on by default). Without them (`default-features = false`) keylo builds
//! without OpenCV, libclang or ONNX Runtime: KISS-ICP, NDT and hybrid registration, the
//! Ouster, KITTI, PLY/PCD and frame-folder readers, and evaluation.
//!
//! Embedding keylo in your own loop (a SLAM front end): [`Frontend`], built from TOML
//! ([`Frontend::from_toml`]) or typed configs ([`Frontend::builder`]); see
//! `docs/embedding.md` and the `examples/` folder.

pub use keylo_core as core;
pub use keylo_eval as eval;
#[cfg(feature = "opencv")]
pub use keylo_features as features;
pub use keylo_io as io;
#[cfg(feature = "opencv")]
pub use keylo_kpeval as kpeval;
pub use keylo_map as map;
#[cfg(feature = "plugins")]
pub use keylo_plugin as plugin;
pub use keylo_registration as registration;
#[cfg(feature = "sim")]
pub use keylo_sim as sim;

pub use keylo_core::*;

mod frontend;

pub use frontend::{DescriptorRow, Error, FrameOutput, Frontend, FrontendBuilder, KeypointView};

/// A registry holding every built-in backend of the enabled keylo crates.
pub fn registry() -> keylo_core::Registry {
    let mut registry = keylo_core::Registry::default();
    #[cfg(feature = "sim")]
    keylo_sim::register(&mut registry);
    keylo_io::register(&mut registry);
    keylo_registration::register(&mut registry);
    keylo_map::localise::register(&mut registry);
    #[cfg(feature = "opencv")]
    keylo_features::register(&mut registry);
    registry
}
