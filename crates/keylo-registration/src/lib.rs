//! keylo registrars and raw-cloud downsamplers.
//!
//! - [`kiss_icp`]: a KISS-ICP-style registrar faithful to upstream PRBonn/kiss-icp
//!   (voxel-hash local map, double voxel downsampling, adaptive threshold, constant-velocity
//!   prediction, deskew, point-to-point ICP with a Geman–McClure kernel).
//! - [`downsample`]: `passthrough` (every valid point) and `voxel` downsamplers.

pub mod downsample;
mod error;
pub mod kiss_icp;
pub mod se3;
pub mod voxel;

pub use error::RegistrationError;
pub use kiss_icp::{KissIcp, KissIcpConfig};

/// Registers this crate's backends: registrar `kiss-icp`, downsamplers `passthrough`, `voxel`.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.registrars.add::<KissIcpConfig>(
        "kiss-icp",
        "KISS-ICP-style point-to-point ICP against a voxel-hash local map (upstream defaults)",
        |config, _ctx| Ok(Box::new(KissIcp::new(config)?)),
    );
    downsample::register(registry);
}
