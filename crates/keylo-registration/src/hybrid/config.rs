//! `[registrar] kind = "hybrid"`: KISS-ICP's parameters for the cloud, plus the keypoint
//! residuals and the degeneracy-aware step.

use serde::{Deserialize, Serialize};

use crate::error::check;
use crate::{KissIcpConfig, RegistrationError};

/// How each Gauss–Newton step is solved.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum HybridSolver {
    /// A second-order-cone program (trust region, bounds in weak directions) with Clarabel;
    /// plain Gauss–Newton for a step where Clarabel fails.
    #[default]
    Clarabel,
    /// Plain Gauss–Newton, clipped to the trust region and the weak-direction bounds.
    GaussNewton,
}

/// The residual of one cloud point against the local map.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum CloudResidual {
    /// KISS-ICP's: the distance to the nearest map point.
    PointToPoint,
    /// The distance to the plane of the map points around the nearest one (their direction
    /// of least spread): no pull along a wall, an edge or a corridor's axis.
    #[default]
    PointToPlane,
}

/// `[registrar] kind = "hybrid"`: point-to-point cloud residuals against KISS-ICP's local map
/// plus robust residuals of descriptor-matched keypoints of consecutive frames.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct HybridConfig {
    /// The cloud part (`[registrar.icp]`): every KISS-ICP parameter, same defaults; its
    /// `degeneracy` table also sets how weak directions are found.
    pub icp: KissIcpConfig,
    /// `point-to-point` (KISS-ICP's) or `point-to-plane` cloud residuals.
    pub cloud_residual: CloudResidual,
    /// Weight of one keypoint pair relative to one cloud residual; with the noise model on, a
    /// pair whose summed point covariance is (5 cm)² I has information I × this weight.
    pub keypoint_weight: f64,
    /// Geman–McClure scale of the keypoint residuals (m).
    pub keypoint_kernel: f64,
    /// Angular noise of a keypoint's ray across it, horizontally (rad; about a pixel of the
    /// image: 0.005 ≈ 0.8 px at 1024 columns). With the two below it gives each keypoint
    /// point a covariance: an angular error moves the point along its surface, by metres on
    /// a wall seen at a grazing angle, so pairs are weighted by their inverse summed
    /// covariance. 0 = every pair weighted alike.
    pub keypoint_sigma_azimuth: f64,
    /// Angular noise of a keypoint's ray, vertically (rad; 0.02 ≈ 0.8 px of 64 rows over 90°).
    pub keypoint_sigma_elevation: f64,
    /// Range noise of a keypoint point (m).
    pub keypoint_sigma_range: f64,
    /// Matched keypoints farther apart than this at the initial guess are dropped (m).
    pub keypoint_max_distance: f64,
    /// Each frame is first aligned with the cloud alone; only the pairs closer than this at
    /// that pose are then used (m). Drops matches of patterns fixed in the image (ground
    /// rings, the ego vehicle, sensor artefacts), which claim "no motion"; 0 = keep every
    /// pair and use the keypoints from the first iteration.
    pub keypoint_gate: f64,
    /// Lowe's ratio for descriptor matches (best below ratio × second best); 1 = off.
    pub match_ratio: f64,
    /// Keep only mutual best matches.
    pub cross_check: bool,
    /// With fewer matched keypoints than this, the weak directions of the cloud are bounded
    /// by `weak_bound` instead of being left to the keypoints.
    pub min_matches: usize,
    /// Remove the cloud's point-to-point terms along its weak directions (there they mostly
    /// pull towards the nearest samples), leaving those directions to the keypoints. Off by
    /// default: on the simulated corridor the little the geometry says along its axis (door
    /// recesses, boxes) is worth keeping (docs/results/hybrid.md).
    pub project_weak: bool,
    /// Largest correction of a frame from the constant-velocity prediction along a weak
    /// direction that the keypoints do not constrain (m; rotations scaled by the RMS range);
    /// 0 = no bound.
    pub weak_bound: f64,
    /// Trust-region radius of one step (m; rotations scaled by the RMS range).
    pub trust_radius: f64,
    /// `clarabel` (convex step with trust region and bounds) or `gauss-newton`.
    pub solver: HybridSolver,
}

impl Default for HybridConfig {
    fn default() -> Self {
        Self {
            icp: KissIcpConfig::default(),
            cloud_residual: CloudResidual::PointToPlane,
            keypoint_weight: 1.0,
            keypoint_kernel: 0.3,
            keypoint_sigma_azimuth: 0.005,
            keypoint_sigma_elevation: 0.02,
            keypoint_sigma_range: 0.02,
            keypoint_max_distance: 1.0,
            keypoint_gate: 0.3,
            match_ratio: 0.8,
            cross_check: true,
            min_matches: 10,
            project_weak: false,
            weak_bound: 0.0,
            trust_radius: 2.0,
            solver: HybridSolver::Clarabel,
        }
    }
}

impl HybridConfig {
    /// The keypoint points' noise model, `None` for equal weights.
    pub(crate) fn point_noise(&self) -> Option<super::uncertainty::PointNoise> {
        (self.keypoint_sigma_azimuth > 0.0).then_some(super::uncertainty::PointNoise {
            azimuth: self.keypoint_sigma_azimuth,
            elevation: self.keypoint_sigma_elevation,
            range: self.keypoint_sigma_range,
        })
    }

    pub(crate) fn validate(&self) -> Result<(), RegistrationError> {
        let positive = |v: f64, max: f64| v.is_finite() && v > 0.0 && v <= max;
        check(
            self.keypoint_weight.is_finite() && (0.0..=1e6).contains(&self.keypoint_weight),
            "keypoint_weight",
            self.keypoint_weight,
            "expected 0 <= keypoint_weight <= 1e6",
        )?;
        check(
            positive(self.keypoint_kernel, 100.0),
            "keypoint_kernel",
            self.keypoint_kernel,
            "expected 0 < keypoint_kernel <= 100 m",
        )?;
        let angle = |v: f64| v.is_finite() && (0.0..=0.5).contains(&v);
        check(
            angle(self.keypoint_sigma_azimuth),
            "keypoint_sigma_azimuth",
            self.keypoint_sigma_azimuth,
            "expected 0 (equal weights) ..= 0.5 rad",
        )?;
        check(
            angle(self.keypoint_sigma_elevation),
            "keypoint_sigma_elevation",
            self.keypoint_sigma_elevation,
            "expected 0 ..= 0.5 rad",
        )?;
        check(
            positive(self.keypoint_sigma_range, 10.0),
            "keypoint_sigma_range",
            self.keypoint_sigma_range,
            "expected 0 < keypoint_sigma_range <= 10 m",
        )?;
        check(
            self.keypoint_gate.is_finite() && (0.0..=1e3).contains(&self.keypoint_gate),
            "keypoint_gate",
            self.keypoint_gate,
            "expected 0 (no gate) ..= 1000 m",
        )?;
        check(
            positive(self.keypoint_max_distance, 1e3),
            "keypoint_max_distance",
            self.keypoint_max_distance,
            "expected 0 < keypoint_max_distance <= 1000 m",
        )?;
        check(
            positive(self.match_ratio, 1.0),
            "match_ratio",
            self.match_ratio,
            "expected 0 < match_ratio <= 1 (1 = no ratio test)",
        )?;
        check(
            self.weak_bound.is_finite() && (0.0..=1e3).contains(&self.weak_bound),
            "weak_bound",
            self.weak_bound,
            "expected 0 <= weak_bound <= 1000 m",
        )?;
        check(
            positive(self.trust_radius, 1e3),
            "trust_radius",
            self.trust_radius,
            "expected 0 < trust_radius <= 1000 m",
        )?;
        Ok(())
    }
}
