//! GICP (Segal et al. 2009, PCL's `GeneralizedIterativeClosestPoint` semantics) and
//! point-to-plane ICP: [`covariances`] (per-point plane patches from k neighbours), [`solve`]
//! (the inner Gauss–Newton problem), [`align`] (PCL's outer loop and convergence rule),
//! [`local_map`] (KISS-ICP's voxel map with covariances) and the [`Gicp`] registrar
//! (`[registrar] kind = "gicp"`, frame to frame or against the local map).

pub mod align;
mod config;
pub mod covariances;
pub mod knn;
pub mod local_map;
mod odometry;
pub mod solve;

pub use align::{align, Cost, GicpCloud, GicpResult, GicpSettings, Neighbour, Target, MIN_POINTS};
pub use config::{GicpConfig, GicpCost, GicpMode};
pub use odometry::Gicp;
