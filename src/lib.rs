//! keylo: keypoint-assisted LiDAR odometry.
//!
//! This facade re-exports the keylo crates and offers [`registry`], the registry with every
//! built-in backend.

pub use keylo_core as core;
pub use keylo_eval as eval;
pub use keylo_features as features;
pub use keylo_io as io;
pub use keylo_kpeval as kpeval;
pub use keylo_plugin as plugin;
pub use keylo_registration as registration;
pub use keylo_sim as sim;

pub use keylo_core::*;

/// A registry holding every built-in backend of every keylo crate.
pub fn registry() -> keylo_core::Registry {
    let mut registry = keylo_core::Registry::default();
    keylo_sim::register(&mut registry);
    keylo_io::register(&mut registry);
    keylo_registration::register(&mut registry);
    keylo_features::register(&mut registry);
    registry
}
