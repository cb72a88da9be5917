//! `hybrid`: degeneracy-aware registration with keypoint matches. Composes KISS-ICP's
//! preprocessing, local map and adaptive threshold ([`crate::kiss_icp`]) with descriptor
//! [`matching`] of consecutive frames' keypoints ([`keypoint_terms`]), the cloud's
//! [`crate::degeneracy`] analysis and a convex [`step`] per Gauss–Newton iteration ([`align`]).
//!
//! Per frame: the cloud's point-to-plane information at the predicted pose gives its weak
//! directions; the keypoint pairs (weight `keypoint_weight` each) constrain them. Optionally
//! (`project_weak`) the cloud's point-to-point terms are removed along them, and with too few
//! pairs the correction along them is bounded (`weak_bound`), so the pose stays near the
//! constant-velocity prediction. Without keypoints (and with the defaults) this is KISS-ICP.

pub mod align;
mod config;
pub mod keypoint_terms;
pub mod matching;
pub mod plane_terms;
pub mod step;
pub mod uncertainty;

pub use config::{CloudResidual, HybridConfig, HybridSolver};

use keylo_core::{CoreError, Degeneracy, FrameKeypoints, PointCloud, Registrar, Registration};
use nalgebra::Isometry3;

use crate::kiss_icp::{deskew, KissIcp, Prepared};
use crate::{degeneracy, frame_step, RegistrationError};
use align::{HybridResult, HybridSettings};
use keypoint_terms::{correspond, Correspondences, MatchRules, PreviousKeypoints};

/// The hybrid odometry state: KISS-ICP's, plus the previous frame's keypoints.
pub struct Hybrid {
    config: HybridConfig,
    icp: KissIcp,
    previous: PreviousKeypoints,
    scratch: Vec<nalgebra::Point3<f64>>,
    normals: plane_terms::NormalCache,
}

/// What one frame gives besides the pose.
struct Outcome {
    result: HybridResult,
    registered: usize,
    degeneracy: Option<Degeneracy>,
}

impl Hybrid {
    /// A registrar with an empty map at the identity pose.
    pub fn new(config: HybridConfig) -> Result<Self, RegistrationError> {
        config.validate()?;
        Ok(Self {
            icp: KissIcp::new(config.icp.clone())?,
            config,
            previous: PreviousKeypoints::default(),
            scratch: Vec::new(),
            normals: plane_terms::NormalCache::default(),
        })
    }

    /// The last estimated pose.
    pub fn pose(&self) -> Isometry3<f64> {
        self.icp.pose()
    }

    /// `keypoints` deskewed as `cloud` is: over the whole scan's time span.
    fn deskewed(&self, keypoints: &FrameKeypoints, cloud: &PointCloud) -> FrameKeypoints {
        let mut out = keypoints.clone();
        let Some(times) = cloud.times.as_deref().filter(|_| self.config.icp.deskew) else {
            return out;
        };
        let span = deskew::time_span(times);
        for image in &mut out.per_image {
            if image.times.len() == image.points.len() {
                deskew::deskew_in_span(
                    &mut image.points,
                    &image.times,
                    span,
                    self.icp.motion_model(),
                );
            }
        }
        out
    }

    /// The settings of this frame's alignment: weak directions of the cloud at the guess.
    fn settings(&mut self, prepared: &Prepared, pairs: &Correspondences) -> HybridSettings {
        let c = &self.config;
        let info = plane_terms::plane_information_cached(
            &prepared.source,
            self.icp.map(),
            &prepared.guess,
            (prepared.settings.max_distance, c.icp.degeneracy.max_points),
            &mut self.normals,
        );
        let d = degeneracy::analyse(
            &info.matrix,
            info.residuals,
            info.rms_range,
            c.icp.degeneracy.weak_ratio,
        );
        HybridSettings {
            icp: prepared.settings,
            keypoint_weight: c.keypoint_weight,
            keypoint_kernel: c.keypoint_kernel,
            keypoint_gate: c.keypoint_gate,
            weak: align::weak_vectors(&d),
            project_weak: c.project_weak,
            bound_weak: c.weak_bound > 0.0 && pairs.len() < c.min_matches,
            weak_bound: c.weak_bound,
            trust_radius: c.trust_radius,
            length_scale: info.rms_range.max(1.0),
            point_to_plane: c.cloud_residual == CloudResidual::PointToPlane,
            clarabel: c.solver == HybridSolver::Clarabel,
        }
    }

    /// The degeneracy report of the aligned cloud (`KissIcp::degeneracy`'s, with the normals
    /// of this frame's cache).
    fn degeneracy(&mut self, prepared: &Prepared, pose: &Isometry3<f64>) -> Option<Degeneracy> {
        let normals = &mut self.normals;
        self.icp
            .degeneracy_with(&prepared.source, |map, max_points| {
                plane_terms::plane_information_cached(
                    &prepared.source,
                    map,
                    pose,
                    (prepared.settings.max_distance, max_points),
                    normals,
                )
            })
    }

    fn register_points(
        &mut self,
        cloud: &PointCloud,
        keypoints: &FrameKeypoints,
    ) -> Result<Outcome, RegistrationError> {
        let keypoints = self.deskewed(keypoints, cloud);
        let prepared = self.icp.prepare(cloud, false)?;
        let rules = MatchRules {
            ratio: self.config.match_ratio,
            cross_check: self.config.cross_check,
            max_distance: self.config.keypoint_max_distance,
            range: (self.config.icp.min_range, self.config.icp.max_range),
            noise: self.config.point_noise(),
        };
        let pairs = correspond(
            &keypoints,
            &self.previous,
            &prepared.guess,
            self.icp.map(),
            &rules,
        );
        let settings = self.settings(&prepared, &pairs);
        let result = align::align(
            &prepared.source,
            self.icp.map(),
            &pairs,
            &prepared.guess,
            &settings,
            (&mut self.scratch, &mut self.normals),
        );
        tracing::debug!(
            "hybrid: {} keypoint pairs ({} inliers), {} weak direction(s) {}, {} iterations ({} in stage 1)",
            pairs.len(),
            result.keypoint_inliers,
            settings.weak.len(),
            if settings.bound_weak {
                "bounded"
            } else {
                "left to the keypoints"
            },
            result.iterations,
            result.stage1_iterations
        );
        if result.fallbacks > 0 {
            tracing::warn!(
                "hybrid: Clarabel failed on {} of {} steps; Gauss–Newton took them",
                result.fallbacks,
                result.iterations
            );
        }
        let degeneracy = self.degeneracy(&prepared, &result.pose);
        let registered = prepared.source.len();
        self.icp.finish(prepared, &result.pose)?;
        self.previous = PreviousKeypoints::placed(
            keypoints,
            &result.pose,
            self.icp.map(),
            rules.noise.as_ref(),
        );
        Ok(Outcome {
            result,
            registered,
            degeneracy,
        })
    }

    fn registration(
        &mut self,
        cloud: &PointCloud,
        keypoints: &FrameKeypoints,
    ) -> Result<Registration, CoreError> {
        frame_step::reject_non_finite(cloud)?;
        let outcome = frame_step::in_own_pool(
            self,
            |s| s.icp.pool_mut(),
            |s| s.register_points(cloud, keypoints),
        )?;
        let r = outcome.result;
        Ok(Registration {
            stamp: frame_step::end_stamp(cloud),
            pose: r.pose,
            source_points: outcome.registered,
            iterations: r.iterations,
            converged: r.converged || r.iterations == 0,
            degeneracy: outcome.degeneracy,
            fit: None,
        })
    }
}

impl Registrar for Hybrid {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        self.registration(cloud, &FrameKeypoints::default())
    }

    fn wants_keypoints(&self) -> bool {
        true
    }

    fn register_with_keypoints(
        &mut self,
        cloud: &PointCloud,
        keypoints: &FrameKeypoints,
    ) -> Result<Registration, CoreError> {
        self.registration(cloud, keypoints)
    }

    /// Three, as the KISS-ICP it runs on (point-to-point).
    fn min_points(&self) -> usize {
        3
    }

    fn map_size(&self) -> usize {
        self.icp.map().len()
    }

    fn set_motion_prior(&mut self, delta: &Isometry3<f64>) -> Result<(), CoreError> {
        self.icp.set_motion_prior(delta)
    }

    fn reset(&mut self) -> Result<(), CoreError> {
        *self = Hybrid::new(self.config.clone())?;
        Ok(())
    }

    fn set_pose(&mut self, pose: &Isometry3<f64>) -> Result<(), CoreError> {
        self.icp.set_pose(pose)
    }

    fn local_map(&self) -> Vec<nalgebra::Point3<f64>> {
        self.icp.local_map()
    }
}
