//! keylo simulator: an Ouster-like spinning LiDAR ray-cast (parry3d BVH, rayon) through
//! textured synthetic scenes, producing organised [`keylo_core::LidarFrame`]s (range, signal,
//! reflectivity, near-IR, points) and the ground-truth trajectory.
//!
//! ```no_run
//! use keylo_sim::{SimConfig, Simulator, SceneKind};
//! let sim = Simulator::new(&SimConfig { scene: SceneKind::Corridor, frames: 10, ..SimConfig::default() })?;
//! let frame = sim.frame(0);
//! let gt = sim.ground_truth();
//! assert_eq!(gt.len(), 10);
//! # Ok::<(), keylo_sim::SimError>(())
//! ```
//!
//! Conventions (see [`sensor`]): sensor frame x forward, y left, z up; row 0 = top beam;
//! column `c` looks at azimuth `π − 2π·c/cols` and fires at `t0 + c/cols · 0.1 s`
//! (destaggered Ouster layout: backward at column 0, forward in the middle).

#![warn(missing_docs)]

pub mod appearance;
pub mod config;
pub mod error;
pub mod mixed_pixels;
pub mod motion;
pub mod noise;
pub mod partial_drops;
mod render;
pub mod scenes;
pub mod sensor;
pub mod shading;
mod simulator;
mod source;
mod stagger;
pub mod texture;
pub mod world;

#[cfg(test)]
mod appearance_tests;
#[cfg(test)]
mod tests;

pub use appearance::Appearance;
pub use config::{SceneKind, SensorKind, SimConfig, ALLOWED_COLUMNS};
pub use error::SimError;
pub use simulator::Simulator;
pub use source::{register, SimSource};
