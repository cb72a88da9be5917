//! keylo registrars and raw-cloud downsamplers.
//!
//! - [`kiss_icp`]: a KISS-ICP-style registrar faithful to upstream PRBonn/kiss-icp
//!   (voxel-hash local map, double voxel downsampling, adaptive threshold, constant-velocity
//!   prediction, deskew, point-to-point ICP with a Geman–McClure kernel).
//! - [`ndt`]: NDT (Magnusson's point-to-distribution, PCL's `NormalDistributionsTransform`
//!   semantics and defaults) in a keyframe local-map odometry like simple_ndt_slam.
//! - [`gicp`]: Generalized ICP (PCL's semantics) and point-to-plane ICP, frame to frame or
//!   against a local map of points with covariances.
//! - [`hybrid`]: KISS-ICP's cloud terms off the weak directions of the geometry plus
//!   keypoint matches of consecutive frames, each step a Clarabel cone program.
//! - [`degeneracy`]: eigen-analysis of the normal equations (weak directions).
//! - [`downsample`]: `passthrough` (every valid point) and `voxel` downsamplers.

pub mod degeneracy;
pub mod downsample;
mod error;
mod frame_step;
pub mod gicp;
pub mod hybrid;
pub mod kiss_icp;
pub mod ndt;
pub mod se3;
#[cfg(test)]
mod test_scenes;
/// Voxel keys and downsampling live in `keylo_core::voxel` (the keypoint downsamplers use
/// them too); re-exported here where the registrars have always found them.
pub use keylo_core::voxel;

use keylo_core::config::StageParams;

pub use error::RegistrationError;
pub use gicp::{Gicp, GicpConfig};
pub use hybrid::{CloudResidual, Hybrid, HybridConfig};
pub use kiss_icp::{EmptyFrame, KissIcp, KissIcpConfig};
pub use ndt::{Ndt, NdtConfig};

keylo_core::stage_params!(KissIcpConfig => "kiss-icp" as RegistrarParams);
keylo_core::stage_params!(HybridConfig => "hybrid" as RegistrarParams);
keylo_core::stage_params!(NdtConfig => "ndt" as RegistrarParams);
keylo_core::stage_params!(GicpConfig => "gicp" as RegistrarParams);

/// Registers this crate's backends: registrars `kiss-icp`, `hybrid`, `ndt`, `gicp`;
/// downsamplers `passthrough`, `voxel`.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.registrars.add::<KissIcpConfig>(
        KissIcpConfig::KIND,
        "KISS-ICP-style point-to-point ICP against a voxel-hash local map (upstream defaults)",
        |config, _ctx| Ok(Box::new(KissIcp::new(config)?)),
    );
    registry.registrars.add::<HybridConfig>(
        HybridConfig::KIND,
        "degeneracy-aware KISS-ICP plus robust residuals of descriptor-matched keypoints of consecutive frames (Clarabel step)",
        |config, _ctx| Ok(Box::new(Hybrid::new(config)?)),
    );
    registry.registrars.add::<NdtConfig>(
        NdtConfig::KIND,
        "NDT (PCL NormalDistributionsTransform semantics) against a local map of recent keyframes",
        |config, _ctx| Ok(Box::new(Ndt::new(config)?)),
    );
    registry.registrars.add::<GicpConfig>(
        GicpConfig::KIND,
        "Generalized ICP (PCL GeneralizedIterativeClosestPoint semantics) or point-to-plane ICP, against a KISS-ICP-style local map or the previous scan",
        |config, _ctx| Ok(Box::new(Gicp::new(config)?)),
    );
    downsample::register(registry);
}
