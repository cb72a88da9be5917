//! `[registrar] kind = "gicp"`: every parameter, its default and its valid range (PCL's
//! names where they mean the same).

use serde::{Deserialize, Serialize};

use super::align::{Cost, GicpSettings};
use crate::degeneracy::DegeneracyConfig;
use crate::error::{check, check_frame_step, check_range_limits, check_voxel_map};
use crate::RegistrationError;

/// What each frame is registered against.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum GicpMode {
    /// A local map built as KISS-ICP builds it (deskew, double voxel downsampling,
    /// constant-velocity guess, voxel-hash map cropped to `max_range`, adaptive threshold),
    /// each map point with its covariance.
    #[default]
    LocalMap,
    /// The previous scan, as PCL's GICP is used: each scan centroid-filtered at
    /// `voxel_size` and aligned to the previous one from the last motion.
    FrameToFrame,
}

/// The cost each pair contributes.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum GicpCost {
    /// Plane-to-plane: `dᵀ (C_t + R C_s Rᵀ)⁻¹ d` (Segal et al. 2009).
    #[default]
    Gicp,
    /// Point-to-plane: the distance along the target point's normal, squared.
    PointToPlane,
}

/// `[registrar] kind = "gicp"`: Generalized ICP (PCL 1.13's `GeneralizedIterativeClosestPoint`
/// semantics and defaults for the alignment) as frame-to-frame or local-map odometry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct GicpConfig {
    /// "local-map" (KISS-ICP-style odometry) or "frame-to-frame" (PCL's use).
    pub mode: GicpMode,
    /// "gicp" (plane-to-plane) or "point-to-plane".
    pub cost: GicpCost,
    /// Pairs farther apart than this are not used, m (PCL `setMaxCorrespondenceDistance`, 5).
    /// In local-map mode with `adaptive_threshold`, 3σ of KISS-ICP's threshold instead.
    pub max_correspondence_distance: f64,
    /// Neighbours of each point's covariance (PCL `setCorrespondenceRandomness`, 20).
    pub k_correspondences: usize,
    /// The covariances' smallest eigenvalue (PCL's `gicp_epsilon`, 0.001).
    pub gicp_epsilon: f64,
    /// Frame to frame: converged when an iteration moves no translation entry by this, m
    /// (PCL 5e-4) …
    pub transformation_epsilon: f64,
    /// … and no rotation-matrix entry by this (PCL 2e-3, about 0.1°).
    pub rotation_epsilon: f64,
    /// Local map: converged when an iteration's motion (twist norm) is below this (KISS-ICP's
    /// rule and value, 1e-4; `transformation_epsilon` and `rotation_epsilon` are frame to
    /// frame's).
    pub convergence_criterion: f64,
    /// Iterations per frame at most (PCL `setMaximumIterations`, 200).
    pub max_iterations: usize,
    /// Voxel edge, m: frame-to-frame, the centroid filter of each scan (0: none); local map,
    /// KISS-ICP's voxel (map points at 0.5×, registered points at 1.5×).
    pub voxel_size: f64,
    /// Local map: points kept per voxel.
    pub max_points_per_voxel: usize,
    /// Local map: the correspondence distance follows KISS-ICP's adaptive threshold (3σ);
    /// false: `max_correspondence_distance`.
    pub adaptive_threshold: bool,
    /// Local map: pairs are down-weighted by KISS-ICP's robust kernel (Geman–McClure, scale
    /// σ of the adaptive threshold, or `max_correspondence_distance`/3), as KISS-ICP's ICP;
    /// false: every pair counts fully, as PCL.
    pub robust_kernel: bool,
    /// Local map: the adaptive threshold's start σ₀, m.
    pub initial_threshold: f64,
    /// Local map: deviations below this (m) do not update the adaptive threshold.
    pub min_motion_th: f64,
    /// Points farther than this from the sensor are dropped; also the local map's radius, m.
    pub max_range: f64,
    /// Points closer than this to the sensor are dropped, m.
    pub min_range: f64,
    /// Motion-compensate each scan with per-point times (constant velocity, as KISS-ICP).
    pub deskew: bool,
    /// Divergence guard: a frame whose pose moves more than this from the previous one (m)
    /// is rejected with an error and the state is kept; 0 disables the guard.
    pub max_motion_per_frame: f64,
    /// Worker threads for this registrar; 0 = the process-wide pool.
    pub max_num_threads: usize,
    /// Per-frame degeneracy analysis (point-to-plane information of the final pairs).
    pub degeneracy: DegeneracyConfig,
}

impl Default for GicpConfig {
    fn default() -> Self {
        let pcl = GicpSettings::default();
        Self {
            mode: GicpMode::LocalMap,
            cost: GicpCost::Gicp,
            max_correspondence_distance: pcl.max_correspondence_distance,
            k_correspondences: 20,
            gicp_epsilon: 1e-3,
            transformation_epsilon: pcl.transformation_epsilon,
            rotation_epsilon: pcl.rotation_epsilon,
            convergence_criterion: 1e-4,
            max_iterations: pcl.max_iterations,
            voxel_size: 1.0,
            max_points_per_voxel: 20,
            adaptive_threshold: true,
            robust_kernel: true,
            initial_threshold: 2.0,
            min_motion_th: 0.1,
            max_range: 100.0,
            min_range: 0.0,
            deskew: true,
            max_motion_per_frame: 5.0,
            max_num_threads: 0,
            degeneracy: DegeneracyConfig::default(),
        }
    }
}

impl GicpConfig {
    /// The alignment's settings with correspondence distance `max_distance` and robust kernel
    /// scale `kernel`.
    pub fn settings(&self, max_distance: f64, kernel: Option<f64>) -> GicpSettings {
        GicpSettings {
            kernel,
            step_convergence: (self.mode == GicpMode::LocalMap)
                .then_some(self.convergence_criterion),
            // Local map: one Gauss–Newton step per pairing, as KISS-ICP (measured on the
            // simulated lab and road: the same ATE to 0.1 mm, 13–20 % faster than solving each
            // pairing to its minimum); frame to frame: each pairing solved as PCL does.
            steps_per_pairing: match self.mode {
                GicpMode::LocalMap => 1,
                GicpMode::FrameToFrame => super::solve::MAX_STEPS,
            },
            max_correspondence_distance: max_distance,
            max_iterations: self.max_iterations,
            transformation_epsilon: self.transformation_epsilon,
            rotation_epsilon: self.rotation_epsilon,
            cost: match self.cost {
                GicpCost::Gicp => Cost::Gicp,
                GicpCost::PointToPlane => Cost::PointToPlane,
            },
        }
    }

    /// Range checks of every parameter; the error names the key.
    pub fn validate(&self) -> Result<(), RegistrationError> {
        let positive = |v: f64, max: f64| v.is_finite() && v > 0.0 && v <= max;
        check_range_limits(self.min_range, self.max_range)?;
        let distances = [
            (
                "max_correspondence_distance",
                self.max_correspondence_distance,
                1e3,
            ),
            ("transformation_epsilon", self.transformation_epsilon, 1.0),
            ("rotation_epsilon", self.rotation_epsilon, 1.0),
            ("convergence_criterion", self.convergence_criterion, 1.0),
            ("initial_threshold", self.initial_threshold, 1e3),
        ];
        for (key, v, max) in distances {
            check(
                positive(v, max),
                key,
                v,
                "expected a finite value above 0 (see docs/config.md)",
            )?;
        }
        check(
            self.gicp_epsilon.is_finite() && self.gicp_epsilon > 0.0 && self.gicp_epsilon <= 1.0,
            "gicp_epsilon",
            self.gicp_epsilon,
            "expected 0 < gicp_epsilon <= 1",
        )?;
        check(
            (3..=1000).contains(&self.k_correspondences),
            "k_correspondences",
            self.k_correspondences,
            "expected 3..=1000",
        )?;
        check(
            (1..=100_000).contains(&self.max_iterations),
            "max_iterations",
            self.max_iterations,
            "expected 1..=100000",
        )?;
        check(
            self.voxel_size.is_finite()
                && (0.0..=1e3).contains(&self.voxel_size)
                && (self.voxel_size > 0.0 || self.mode == GicpMode::FrameToFrame),
            "voxel_size",
            self.voxel_size,
            "expected 0 < voxel_size <= 1000 m (0, no filter, only in frame-to-frame mode)",
        )?;
        check_voxel_map(self.max_points_per_voxel, self.min_motion_th)?;
        check_frame_step(self.max_motion_per_frame, self.max_num_threads)?;
        self.degeneracy.validate()
    }
}
