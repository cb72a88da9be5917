//! `[registrar] kind = "ndt"`: every parameter, its default and its valid range.

use serde::{Deserialize, Serialize};

use super::align::AlignSettings;
use super::neighbours::NeighbourSearch;
use super::voxel_grid::GridSettings;
use crate::degeneracy::DegeneracyConfig;
use crate::error::{check, check_frame_step, check_range_limits};
use crate::RegistrationError;

/// `[registrar] kind = "ndt"`: PCL's `NormalDistributionsTransform` (defaults of PCL 1.13
/// except `transformation_epsilon`) inside a simple_ndt_slam-style odometry (keyframe local map, constant velocity).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct NdtConfig {
    /// NDT voxel edge (m): one Gaussian per target voxel (PCL `setResolution`, 1.0).
    pub resolution: f64,
    /// Longest line-search step along the normalised Newton direction, in the units of
    /// [x y z roll pitch yaw] (PCL `setStepSize`, 0.1).
    pub step_size: f64,
    /// Stop when a Newton step's squared translation (m²) is at most this; ≤ 0 leaves only
    /// `rotation_epsilon`. Also twice the line search's shortest step (PCL
    /// `setTransformationEpsilon`). The one default that differs from PCL's (0.1): with 0.1
    /// every frame stops after one step of 0.05–0.1 m, which drifts (1.5 m ATE on 30 simulated
    /// lab frames, 0.0095 m with 1e-4; docs/results/ndt-parity.md).
    pub transformation_epsilon: f64,
    /// Stop when a Newton step's rotation has cos(angle) at least this; 0 = unused (PCL
    /// `setTransformationRotationEpsilon`, unset).
    pub rotation_epsilon: f64,
    /// Newton iterations per frame at most (PCL `setMaximumIterations`, 35).
    pub max_iterations: usize,
    /// Share of points expected to be outliers in the Gaussian-plus-uniform score (PCL
    /// `setOulierRatio`, 0.55).
    pub outlier_ratio: f64,
    /// Target voxels with fewer points are not used (PCL: 6).
    pub min_points_per_voxel: usize,
    /// Covariance eigenvalues below this fraction of the largest are raised to it, so flat or
    /// linear voxels stay invertible (PCL: 0.01).
    pub min_eigenvalue_ratio: f64,
    /// Target voxels a source point is scored against: "radius" (every voxel mean within one
    /// resolution, k-d tree; PCL's default), "direct7" (own voxel + 6 face neighbours),
    /// "direct1" (own voxel).
    pub neighbour_search: NeighbourSearch,
    /// Points closer than this to the sensor are dropped (m).
    pub min_range: f64,
    /// Points farther than this from the sensor are dropped (m).
    pub max_range: f64,
    /// Voxel edge of the centroid filter applied to the scan before matching (m); 0 = none
    /// (simple_ndt_slam `voxel_leaf_size`).
    pub source_voxel_size: f64,
    /// Voxel edge of the centroid filter applied to a keyframe before it enters the local
    /// map (m); 0 = none.
    pub map_voxel_size: f64,
    /// A frame becomes a keyframe once it is this far (m) from the last keyframe
    /// (simple_ndt_slam `min_add_scan_shift`).
    pub keyframe_distance: f64,
    /// ... or once it has turned this much (degrees) from the last keyframe.
    pub keyframe_angle: f64,
    /// Keyframes in the local map (the oldest is dropped).
    pub local_map_keyframes: usize,
    /// Motion-compensate each scan with per-point times (constant velocity, as kiss-icp).
    pub deskew: bool,
    /// Divergence guard: a frame whose pose moves more than this from the previous one (m) is
    /// rejected with an error and the state is kept; 0 disables the guard.
    pub max_motion_per_frame: f64,
    /// Worker threads for this registrar; 0 = the process-wide pool.
    pub max_num_threads: usize,
    /// Per-frame degeneracy analysis (point-to-plane information of the aligned source
    /// against the target's planar voxel Gaussians; see `ndt::degeneracy`).
    pub degeneracy: DegeneracyConfig,
}

impl Default for NdtConfig {
    fn default() -> Self {
        let grid = GridSettings::default();
        let solver = AlignSettings::default();
        Self {
            resolution: grid.resolution,
            step_size: solver.step_size,
            transformation_epsilon: 1e-4,
            rotation_epsilon: solver.rotation_epsilon,
            max_iterations: solver.max_iterations,
            outlier_ratio: solver.outlier_ratio,
            min_points_per_voxel: grid.min_points_per_voxel,
            min_eigenvalue_ratio: grid.min_eigenvalue_ratio,
            neighbour_search: NeighbourSearch::default(),
            min_range: 0.0,
            max_range: 100.0,
            source_voxel_size: 0.5,
            map_voxel_size: 0.2,
            keyframe_distance: 1.0,
            keyframe_angle: 15.0,
            local_map_keyframes: 10,
            deskew: true,
            max_motion_per_frame: 5.0,
            max_num_threads: 0,
            degeneracy: DegeneracyConfig::default(),
        }
    }
}

impl NdtConfig {
    /// The target-grid part.
    pub fn grid(&self) -> GridSettings {
        GridSettings {
            resolution: self.resolution,
            min_points_per_voxel: self.min_points_per_voxel,
            min_eigenvalue_ratio: self.min_eigenvalue_ratio,
        }
    }

    /// The solver part.
    pub fn solver(&self) -> AlignSettings {
        AlignSettings {
            step_size: self.step_size,
            transformation_epsilon: self.transformation_epsilon,
            rotation_epsilon: self.rotation_epsilon,
            max_iterations: self.max_iterations,
            outlier_ratio: self.outlier_ratio,
        }
    }

    /// Range checks of every parameter.
    pub fn validate(&self) -> Result<(), RegistrationError> {
        let pos = |v: f64, max: f64| v.is_finite() && v > 0.0 && v <= max;
        let zero_or = |v: f64, max: f64| v == 0.0 || pos(v, max);
        check(
            pos(self.resolution, 1e3),
            "resolution",
            self.resolution,
            "expected 0 < resolution <= 1000 m",
        )?;
        check(
            pos(self.step_size, 10.0),
            "step_size",
            self.step_size,
            "expected 0 < step_size <= 10",
        )?;
        check(
            self.transformation_epsilon.is_finite()
                && self.transformation_epsilon < 2.0 * self.step_size,
            "transformation_epsilon",
            self.transformation_epsilon,
            "expected a finite value < 2 × step_size (it is also twice the shortest step)",
        )?;
        check(
            (0.0..=1.0).contains(&self.rotation_epsilon),
            "rotation_epsilon",
            self.rotation_epsilon,
            "expected 0 (unused) ..= 1 (a cosine)",
        )?;
        check(
            (1..=10_000).contains(&self.max_iterations),
            "max_iterations",
            self.max_iterations,
            "expected 1..=10000",
        )?;
        check(
            self.outlier_ratio.is_finite() && self.outlier_ratio > 0.0 && self.outlier_ratio < 1.0,
            "outlier_ratio",
            self.outlier_ratio,
            "expected 0 < outlier_ratio < 1",
        )?;
        check(
            (3..=100_000).contains(&self.min_points_per_voxel),
            "min_points_per_voxel",
            self.min_points_per_voxel,
            "expected 3..=100000 (a covariance needs 3 points)",
        )?;
        check(
            self.min_eigenvalue_ratio.is_finite()
                && self.min_eigenvalue_ratio > 0.0
                && self.min_eigenvalue_ratio <= 1.0,
            "min_eigenvalue_ratio",
            self.min_eigenvalue_ratio,
            "expected 0 < min_eigenvalue_ratio <= 1",
        )?;
        check_range_limits(self.min_range, self.max_range)?;
        check(
            zero_or(self.source_voxel_size, 1e3),
            "source_voxel_size",
            self.source_voxel_size,
            "expected 0 (none) or 0 < v <= 1000 m",
        )?;
        check(
            zero_or(self.map_voxel_size, 1e3),
            "map_voxel_size",
            self.map_voxel_size,
            "expected 0 (none) or 0 < v <= 1000 m",
        )?;
        check(
            self.keyframe_distance.is_finite() && self.keyframe_distance >= 0.0,
            "keyframe_distance",
            self.keyframe_distance,
            "expected >= 0 m",
        )?;
        check(
            self.keyframe_angle.is_finite() && self.keyframe_angle >= 0.0,
            "keyframe_angle",
            self.keyframe_angle,
            "expected >= 0 degrees",
        )?;
        check(
            (1..=10_000).contains(&self.local_map_keyframes),
            "local_map_keyframes",
            self.local_map_keyframes,
            "expected 1..=10000",
        )?;
        check_frame_step(self.max_motion_per_frame, self.max_num_threads)?;
        self.degeneracy.validate()
    }
}
