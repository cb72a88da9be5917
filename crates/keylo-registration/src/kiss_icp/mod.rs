//! KISS-ICP-style registrar: composes [`deskew`], voxel downsampling, [`threshold`],
//! [`icp`] and the [`voxel_map`], as upstream's `KissICP::RegisterFrame`.

mod config;
pub mod deskew;
pub mod icp;
pub(crate) mod neighbours;
pub mod threshold;
mod time_table;
pub mod voxel_map;

use crate::frame_step;
use keylo_core::{CoreError, PointCloud, Registrar, Registration};
use nalgebra::{Isometry3, Point3};

use crate::degeneracy;
use crate::{voxel, RegistrationError};
use icp::{IcpResult, IcpSettings};
use keylo_core::Degeneracy;
use threshold::AdaptiveThreshold;
use voxel_map::{MapLimits, VoxelHashMap};

pub use config::{EmptyFrame, KissIcpConfig};

/// The KISS-ICP odometry state.
pub struct KissIcp {
    config: KissIcpConfig,
    voxel_size: f64,
    map: VoxelHashMap,
    threshold: AdaptiveThreshold,
    last_pose: Isometry3<f64>,
    last_delta: Isometry3<f64>,
    pool: Option<rayon::ThreadPool>,
    scratch: Vec<Point3<f64>>,
    grid: voxel::UpstreamGrid,
    frame_downsample: Vec<Point3<f64>>,
    source: Vec<Point3<f64>>,
    /// The deskewed, cropped scan (a buffer reused between frames).
    preprocessed: Vec<Point3<f64>>,
    /// An external motion prior for the next frame (`Registrar::set_motion_prior`).
    prior: Option<Isometry3<f64>>,
}

impl KissIcp {
    /// A registrar with an empty map at the identity pose.
    pub fn new(config: KissIcpConfig) -> Result<Self, RegistrationError> {
        config.validate()?;
        let voxel_size = config.effective_voxel_size();
        let pool = frame_step::own_pool(config.max_num_threads)?;
        Ok(Self {
            map: VoxelHashMap::new(voxel_size, config.max_range, config.max_points_per_voxel)
                .with_limits(MapLimits {
                    max_points: config.max_map_points,
                    max_age: config.max_voxel_age,
                }),
            threshold: AdaptiveThreshold::new(
                config.initial_threshold,
                config.min_motion_th,
                config.max_range,
            ),
            voxel_size,
            config,
            last_pose: Isometry3::identity(),
            last_delta: Isometry3::identity(),
            pool,
            scratch: Vec::new(),
            grid: voxel::UpstreamGrid::default(),
            frame_downsample: Vec::new(),
            source: Vec::new(),
            preprocessed: Vec::new(),
            prior: None,
        })
    }

    /// The local map's points (world frame).
    pub fn local_map(&self) -> Vec<Point3<f64>> {
        self.map.points()
    }

    /// The last estimated pose.
    pub fn pose(&self) -> Isometry3<f64> {
        self.last_pose
    }

    /// Deskew with the motion `delta` and range filter, as upstream's `Preprocessor`, into
    /// `out`.
    fn preprocess(&self, cloud: &PointCloud, delta: &Isometry3<f64>, out: &mut Vec<Point3<f64>>) {
        let range = (self.config.min_range, self.config.max_range);
        frame_step::deskew_and_crop_into(cloud, self.config.deskew, delta, range, out);
    }

    /// The motion the next frame is predicted and deskewed with: the external prior when one
    /// is set, else the last frame-to-frame motion (constant velocity).
    pub(crate) fn motion_model(&self) -> &Isometry3<f64> {
        self.prior.as_ref().unwrap_or(&self.last_delta)
    }

    fn sigma(&self) -> f64 {
        if self.config.fixed_threshold > 0.0 {
            self.config.fixed_threshold
        } else {
            self.threshold.threshold()
        }
    }

    /// Rejects a non-finite pose or one that jumped beyond `max_motion_per_frame`.
    fn check_divergence(&self, pose: &Isometry3<f64>) -> Result<(), RegistrationError> {
        let finite = keylo_core::rigid::is_finite(pose);
        let step = (self.last_pose.inverse() * pose).translation.vector.norm();
        let bound = self.config.max_motion_per_frame;
        if !finite || (bound > 0.0 && step > bound) {
            return Err(RegistrationError::Diverged(format!(
                "diverged: the pose moved {step:.3} m in one frame (bound `max_motion_per_frame` = {bound} m)"
            )));
        }
        Ok(())
    }

    /// Deskews, crops and downsamples a cloud and predicts its pose: everything before the
    /// alignment (shared with the `hybrid` registrar).
    /// With `allow_empty` a frame with no point in range is prepared too (its alignment
    /// returns the prediction); otherwise it is an error.
    pub(crate) fn prepare(
        &mut self,
        cloud: &PointCloud,
        allow_empty: bool,
    ) -> Result<Prepared, RegistrationError> {
        let delta = self.prior.take().unwrap_or(self.last_delta);
        let mut frame = std::mem::take(&mut self.preprocessed);
        self.preprocess(cloud, &delta, &mut frame);
        if frame.is_empty() && !allow_empty {
            self.preprocessed = frame;
            return Err(frame_step::nothing_in_range(
                cloud,
                (self.config.min_range, self.config.max_range),
            ));
        }
        // Upstream's point order, so that the 1.5× downsampling and the map update select
        // the same points as upstream (see `voxel::downsample_upstream_order`).
        let (mut frame_downsample, mut source) = (
            std::mem::take(&mut self.frame_downsample),
            std::mem::take(&mut self.source),
        );
        self.grid
            .downsample_into(&frame, self.voxel_size * 0.5, &mut frame_downsample);
        self.grid
            .downsample_into(&frame_downsample, self.voxel_size * 1.5, &mut source);
        self.preprocessed = frame;
        let sigma = self.sigma();
        let settings = IcpSettings {
            max_iterations: self.config.max_num_iterations,
            convergence: self.config.convergence_criterion,
            max_distance: 3.0 * sigma,
            kernel: sigma,
        };
        Ok(Prepared {
            frame_downsample,
            source,
            guess: self.last_pose * delta,
            settings,
        })
    }

    /// Accepts `new_pose` for a prepared frame: divergence guard, threshold and map update,
    /// motion model. On an error the state is as before the frame.
    pub(crate) fn finish(
        &mut self,
        prepared: Prepared,
        new_pose: &Isometry3<f64>,
    ) -> Result<(), RegistrationError> {
        let Prepared {
            frame_downsample,
            source,
            guess,
            ..
        } = prepared;
        let checked = self.check_divergence(new_pose);
        if checked.is_ok() {
            self.threshold.update(&(guess.inverse() * new_pose));
            self.map.update(&frame_downsample, new_pose);
            self.last_delta = self.last_pose.inverse() * new_pose;
            // Unit quaternions drift off unit norm through repeated products; the error
            // compounds geometrically through `last_pose⁻¹ · new_pose`, so renormalise every
            // frame.
            self.last_delta.rotation.renormalize();
            self.last_pose = *new_pose;
        }
        (self.frame_downsample, self.source) = (frame_downsample, source);
        checked
    }

    /// The local map.
    pub(crate) fn map(&self) -> &VoxelHashMap {
        &self.map
    }

    /// The registrar's own thread pool slot.
    pub(crate) fn pool_mut(&mut self) -> &mut Option<rayon::ThreadPool> {
        &mut self.pool
    }

    /// The degeneracy of `source` at `pose` against the map (before the map update).
    pub(crate) fn degeneracy(
        &self,
        source: &[Point3<f64>],
        pose: &Isometry3<f64>,
        max_distance: f64,
    ) -> Option<Degeneracy> {
        self.degeneracy_with(source, |map, max_points| {
            degeneracy::plane_information(source, map, pose, max_distance, max_points)
        })
    }

    /// The degeneracy report (when `[registrar.degeneracy] analyse` and there is a map and a
    /// cloud) from the information `info(map, max_points)` gives.
    pub(crate) fn degeneracy_with(
        &self,
        source: &[Point3<f64>],
        info: impl FnOnce(&VoxelHashMap, usize) -> degeneracy::PlaneInformation,
    ) -> Option<Degeneracy> {
        let c = &self.config.degeneracy;
        if !c.analyse || self.map.is_empty() || source.is_empty() {
            return None;
        }
        let info = info(&self.map, c.max_points);
        Some(degeneracy::analyse(
            &info.matrix,
            info.residuals,
            info.rms_range,
            c.weak_ratio,
        ))
    }

    fn register_points(
        &mut self,
        cloud: &PointCloud,
    ) -> Result<(IcpResult, usize, Option<Degeneracy>), RegistrationError> {
        let allow_empty = self.config.empty_frame == EmptyFrame::Predict;
        let prepared = self.prepare(cloud, allow_empty)?;
        if prepared.source.is_empty() && !cloud.is_empty() {
            // Say why (points beyond max_range may be a unit problem); the caller names the
            // frame.
            let why =
                frame_step::nothing_in_range(cloud, (self.config.min_range, self.config.max_range));
            tracing::warn!("the pose is predicted: {why}");
        }
        let result = icp::align(
            &prepared.source,
            &self.map,
            &prepared.guess,
            &prepared.settings,
            &mut self.scratch,
        );
        let degeneracy = self.degeneracy(
            &prepared.source,
            &result.pose,
            prepared.settings.max_distance,
        );
        let registered = prepared.source.len();
        self.finish(prepared, &result.pose)?;
        Ok((result, registered, degeneracy))
    }
}

/// A frame made ready for alignment by [`KissIcp::prepare`].
pub(crate) struct Prepared {
    /// The scan at half the voxel size (what enters the map).
    pub(crate) frame_downsample: Vec<Point3<f64>>,
    /// The points to align.
    pub(crate) source: Vec<Point3<f64>>,
    /// The constant-velocity prediction.
    pub(crate) guess: Isometry3<f64>,
    pub(crate) settings: IcpSettings,
}

impl Registrar for KissIcp {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        frame_step::reject_non_finite(cloud)?;
        let outcome = frame_step::in_own_pool(self, |s| &mut s.pool, |s| s.register_points(cloud));
        let (result, source_points, degeneracy) = outcome?;
        Ok(Registration {
            stamp: frame_step::end_stamp(cloud),
            pose: result.pose,
            source_points,
            iterations: result.iterations,
            // The first frame has no map to align to: nothing to converge.
            converged: result.converged || result.iterations == 0,
            degeneracy,
            fit: None,
        })
    }

    fn map_size(&self) -> usize {
        self.map.len()
    }

    fn accepts_empty_clouds(&self) -> bool {
        self.config.empty_frame == EmptyFrame::Predict
    }

    /// Three: point-to-point residuals of three non-collinear points fix a rigid motion.
    fn min_points(&self) -> usize {
        3
    }

    fn set_motion_prior(&mut self, delta: &Isometry3<f64>) -> Result<(), CoreError> {
        frame_step::check_prior(delta, self.config.max_motion_per_frame)?;
        self.prior = Some(*delta);
        Ok(())
    }

    fn reset(&mut self) -> Result<(), CoreError> {
        *self = KissIcp::new(self.config.clone())?;
        Ok(())
    }

    fn set_pose(&mut self, pose: &Isometry3<f64>) -> Result<(), CoreError> {
        frame_step::check_rigid(pose, "pose")?;
        self.last_pose = *pose;
        Ok(())
    }

    fn local_map(&self) -> Vec<Point3<f64>> {
        self.map.points()
    }
}
