//! `[registrar] kind = "kiss-icp"`: its parameters, their upstream defaults and their checks.

use serde::{Deserialize, Serialize};

use crate::degeneracy::DegeneracyConfig;
use crate::error::{check, check_frame_step, check_range_limits, check_voxel_map};
use crate::RegistrationError;

/// `[registrar] kind = "kiss-icp"`: parameters and defaults of upstream KISS-ICP.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct KissIcpConfig {
    /// Points farther than this from the sensor are dropped; also the local-map radius (m).
    pub max_range: f64,
    /// Points closer than this to the sensor are dropped (m).
    pub min_range: f64,
    /// Motion-compensate each scan with per-point times (constant velocity).
    pub deskew: bool,
    /// Map voxel edge (m); 0 means max_range / 100, as upstream.
    pub voxel_size: f64,
    /// Points kept per map voxel.
    pub max_points_per_voxel: usize,
    /// Bound on the local map's points: beyond it the least recently seen voxels are dropped
    /// (down to 95 %); 0 = unbounded (upstream: only the `max_range` crop bounds the map).
    pub max_map_points: usize,
    /// Frames a map voxel may go without a new point before it is dropped; 0 = never
    /// (upstream). Bounds the map in a closed space, where the range crop never bites.
    pub max_voxel_age: u64,
    /// Initial adaptive threshold σ₀ (m).
    pub initial_threshold: f64,
    /// Deviations below this (m) do not update the adaptive threshold.
    pub min_motion_th: f64,
    /// Fixed correspondence threshold σ (m) instead of the adaptive one; 0 = adaptive.
    pub fixed_threshold: f64,
    /// ICP iterations per frame at most.
    pub max_num_iterations: usize,
    /// ICP stops when the update's norm falls below this.
    pub convergence_criterion: f64,
    /// Worker threads for this registrar; 0 = the process-wide pool.
    pub max_num_threads: usize,
    /// Divergence guard: a frame whose pose moves more than this from the previous one (m) is
    /// rejected with an error and the state is kept; 0 disables the guard.
    pub max_motion_per_frame: f64,
    /// Per-frame degeneracy analysis (point-to-plane information at convergence).
    pub degeneracy: DegeneracyConfig,
    /// A frame with no point to register (an empty scan, or none within the range limits):
    /// `predict` gives it the constant-velocity prediction and goes on, as upstream does
    /// (the run reports such frames); `error` stops it with an error naming the frame.
    /// The `hybrid` registrar always stops.
    pub empty_frame: EmptyFrame,
}

/// `empty_frame`: what a frame without a point to register gets.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum EmptyFrame {
    /// The motion model's prediction (upstream KISS-ICP's behaviour).
    #[default]
    Predict,
    /// An error naming the frame.
    Error,
}

impl Default for KissIcpConfig {
    fn default() -> Self {
        Self {
            max_range: 100.0,
            min_range: 0.0,
            deskew: true,
            voxel_size: 0.0,
            max_points_per_voxel: 20,
            max_map_points: 2_000_000,
            max_voxel_age: 0,
            initial_threshold: 2.0,
            min_motion_th: 0.1,
            fixed_threshold: 0.0,
            max_num_iterations: 500,
            convergence_criterion: 1e-4,
            max_num_threads: 0,
            max_motion_per_frame: 5.0,
            degeneracy: DegeneracyConfig::default(),
            empty_frame: EmptyFrame::Predict,
        }
    }
}

impl KissIcpConfig {
    /// The voxel size in use (`voxel_size`, or `max_range / 100` when 0).
    pub fn effective_voxel_size(&self) -> f64 {
        if self.voxel_size > 0.0 {
            self.voxel_size
        } else {
            self.max_range / 100.0
        }
    }

    pub(super) fn validate(&self) -> Result<(), RegistrationError> {
        // Upper bounds keep every derived quantity (σ², kernel weights) finite.
        let in_range = |v: f64, max: f64| v.is_finite() && v > 0.0 && v <= max;
        let zero_or = |v: f64, max: f64| v == 0.0 || in_range(v, max);
        check_range_limits(self.min_range, self.max_range)?;
        check(
            zero_or(self.voxel_size, 1e3),
            "voxel_size",
            self.voxel_size,
            "expected 0 (= max_range/100) or 0 < voxel_size <= 1000 m",
        )?;
        check(
            in_range(self.initial_threshold, 1e3),
            "initial_threshold",
            self.initial_threshold,
            "expected 0 < initial_threshold <= 1000 m",
        )?;
        check(
            zero_or(self.fixed_threshold, 1e3),
            "fixed_threshold",
            self.fixed_threshold,
            "expected 0 (= adaptive) or 0 < fixed_threshold <= 1000 m",
        )?;
        check(
            self.max_map_points == 0 || self.max_map_points >= 1000,
            "max_map_points",
            self.max_map_points,
            "expected 0 (unbounded) or >= 1000 points",
        )?;
        check(
            (1..=100_000).contains(&self.max_num_iterations),
            "max_num_iterations",
            self.max_num_iterations,
            "expected 1..=100000",
        )?;
        check(
            in_range(self.convergence_criterion, 1.0),
            "convergence_criterion",
            self.convergence_criterion,
            "expected 0 < convergence_criterion <= 1",
        )?;
        check_voxel_map(self.max_points_per_voxel, self.min_motion_th)?;
        check_frame_step(self.max_motion_per_frame, self.max_num_threads)?;
        self.degeneracy.validate()
    }
}
