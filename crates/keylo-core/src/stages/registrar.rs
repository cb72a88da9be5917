use crate::{CoreError, PointCloud, Pose};

/// The outcome of registering one cloud.
#[derive(Debug, Clone, PartialEq)]
pub struct Registration {
    /// Time the pose refers to, seconds: the instant the registrar deskews the scan to
    /// (KISS-ICP: the end of the scan; the scan start when the cloud has no per-point times).
    pub stamp: f64,
    /// Pose of the sensor at `stamp` in the world (first-frame) frame.
    pub pose: Pose,
    /// Points used for registration after the registrar's own preprocessing.
    pub source_points: usize,
    /// Iterations the solver ran.
    pub iterations: usize,
    /// Whether the solver met its convergence rule (false: stopped at the iteration cap).
    pub converged: bool,
}

/// Estimates the sensor pose of each cloud against its own local map (odometry).
///
/// Owns: the local map, the motion model and everything needed between frames. Clouds arrive in
/// time order; an error leaves the state as it was before the call.
pub trait Registrar: Send {
    /// Registers the next cloud and returns its pose.
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError>;
    /// Points currently in the local map.
    fn map_size(&self) -> usize;
}
