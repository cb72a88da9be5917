//! NDT registrar (Magnusson's point-to-distribution NDT with PCL's
//! `NormalDistributionsTransform` semantics) in a simple_ndt_slam-style odometry. Composes
//! [`voxel_grid`] (target Gaussians), [`neighbours`] (search modes), [`score`] (score,
//! gradient, Hessian), [`line_search`] (More–Thuente), [`align`] (the Newton loop) and
//! [`odometry`] (keyframe local map), with deskew and the constant-velocity guess of kiss-icp.
//!
//! Aligning one cloud to another, as PCL's `align`:
//!
//! ```
//! use keylo_registration::ndt::{align, AlignSettings, GridSettings, NdtTarget, NeighbourSearch};
//! use nalgebra::{Isometry3, Point3};
//! // A corner of three wavy planes, and the same points seen from 0.1 m further along x.
//! let mut target = Vec::new();
//! for i in 0..40 {
//!     for j in 0..40 {
//!         let (a, b) = (f64::from(i) * 0.1, f64::from(j) * 0.1);
//!         target.push(Point3::new(a, b, 0.1 * (a * 2.0).sin()));
//!         target.push(Point3::new(a, 0.1 * (b * 2.0).cos(), b));
//!         target.push(Point3::new(0.1 * (a * 3.0).sin(), a, b));
//!     }
//! }
//! let source: Vec<_> = target.iter().map(|p| p - nalgebra::Vector3::new(0.1, 0.0, 0.0)).collect();
//! let grid = NdtTarget::new(&target, &GridSettings::default(), NeighbourSearch::Radius)?;
//! let settings = AlignSettings { transformation_epsilon: 1e-6, ..AlignSettings::default() };
//! let r = align(&grid, &source, &Isometry3::identity(), &settings)?;
//! assert!((r.pose.translation.vector.x - 0.1).abs() < 0.02, "{}", r.pose);
//! # Ok::<(), keylo_registration::RegistrationError>(())
//! ```

pub mod align;
mod config;
pub mod degeneracy;
pub mod euler;
pub mod line_search;
pub mod neighbours;
pub mod odometry;
pub mod score;
pub mod voxel_grid;

use crate::frame_step;
use keylo_core::{CoreError, Degeneracy, PointCloud, Registrar, Registration};
use nalgebra::{Isometry3, Point3};

pub use align::{align, AlignSettings, NdtResult};
pub use config::NdtConfig;
pub use neighbours::{NdtTarget, NeighbourSearch};
pub use voxel_grid::GridSettings;

use crate::{voxel, RegistrationError};
use odometry::{LocalMap, MapSettings};

/// The NDT odometry state.
pub struct Ndt {
    config: NdtConfig,
    map: LocalMap,
    last_pose: Isometry3<f64>,
    last_delta: Isometry3<f64>,
    pool: Option<rayon::ThreadPool>,
    /// An external motion prior for the next frame (`Registrar::set_motion_prior`).
    prior: Option<Isometry3<f64>>,
}

impl Ndt {
    /// A registrar with an empty map at the identity pose.
    pub fn new(config: NdtConfig) -> Result<Self, RegistrationError> {
        config.validate()?;
        let pool = frame_step::own_pool(config.max_num_threads)?;
        let settings = MapSettings {
            keyframe_distance: config.keyframe_distance,
            keyframe_angle: config.keyframe_angle.to_radians(),
            keyframes: config.local_map_keyframes,
            voxel_size: config.map_voxel_size,
        };
        Ok(Self {
            map: LocalMap::new(settings, config.grid(), config.neighbour_search),
            config,
            last_pose: Isometry3::identity(),
            last_delta: Isometry3::identity(),
            pool,
            prior: None,
        })
    }

    /// The last estimated pose.
    pub fn pose(&self) -> Isometry3<f64> {
        self.last_pose
    }

    /// Deskew with the motion `delta` and range filter.
    fn preprocess(&self, cloud: &PointCloud, delta: &Isometry3<f64>) -> Vec<Point3<f64>> {
        let range = (self.config.min_range, self.config.max_range);
        frame_step::deskew_and_crop(cloud, self.config.deskew, delta, range)
    }

    /// Rejects a non-finite pose or one that jumped beyond `max_motion_per_frame`.
    fn check_divergence(&self, pose: &Isometry3<f64>) -> Result<(), RegistrationError> {
        frame_step::check_motion(
            "NDT",
            &self.last_pose,
            pose,
            self.config.max_motion_per_frame,
        )
    }

    fn register_points(
        &mut self,
        cloud: &PointCloud,
    ) -> Result<(NdtResult, usize, Option<Degeneracy>), RegistrationError> {
        // The external prior when one is set, else constant velocity.
        let delta = self.prior.take().unwrap_or(self.last_delta);
        let frame = self.preprocess(cloud, &delta);
        if frame.is_empty() {
            return Err(frame_step::nothing_in_range(
                cloud,
                (self.config.min_range, self.config.max_range),
            ));
        }
        let source = match self.config.source_voxel_size {
            v if v > 0.0 => voxel::centroids(&frame, v),
            _ => frame.clone(),
        };
        let Some(target) = self.map.target() else {
            // The first frame: nothing to align to; it founds the map.
            self.map.add_keyframe(&frame, &self.last_pose)?;
            let first = NdtResult {
                pose: self.last_pose,
                iterations: 0,
                converged: true,
                likelihood: 0.0,
                hessian: nalgebra::Matrix6::zeros(),
            };
            return Ok((first, source.len(), None));
        };
        let guess = self.last_pose * delta;
        let result = align(target, &source, &guess, &self.config.solver())?;
        self.check_divergence(&result.pose)?;
        let degeneracy = self.degeneracy(target, &source, &result.pose);
        if self.map.wants_keyframe(&result.pose) {
            self.map.add_keyframe(&frame, &result.pose)?;
        }
        self.last_delta = self.last_pose.inverse() * result.pose;
        self.last_delta.rotation.renormalize();
        self.last_pose = result.pose;
        Ok((result, source.len(), degeneracy))
    }
}

impl Ndt {
    /// The point-to-plane degeneracy of the aligned `source` against the target (before the
    /// map update), rotations scaled by the RMS range of the points that found a plane.
    fn degeneracy(
        &self,
        target: &NdtTarget,
        source: &[Point3<f64>],
        pose: &Isometry3<f64>,
    ) -> Option<Degeneracy> {
        let c = &self.config.degeneracy;
        if !c.analyse {
            return None;
        }
        let info = degeneracy::plane_information(target, source, pose, c.max_points);
        Some(crate::degeneracy::analyse(
            &info.matrix,
            info.residuals,
            info.rms_range,
            c.weak_ratio,
        ))
    }
}

impl Registrar for Ndt {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        frame_step::reject_non_finite(cloud)?;
        let outcome = frame_step::in_own_pool(self, |s| &mut s.pool, |s| s.register_points(cloud));
        let (result, source_points, degeneracy) = outcome?;
        Ok(Registration {
            stamp: frame_step::end_stamp(cloud),
            pose: result.pose,
            source_points,
            iterations: result.iterations,
            converged: result.converged,
            degeneracy,
            fit: None,
        })
    }

    fn map_size(&self) -> usize {
        self.map.len()
    }

    fn set_motion_prior(&mut self, delta: &Isometry3<f64>) -> Result<(), CoreError> {
        frame_step::check_prior(delta, self.config.max_motion_per_frame)?;
        self.prior = Some(*delta);
        Ok(())
    }

    fn reset(&mut self) -> Result<(), CoreError> {
        *self = Ndt::new(self.config.clone())?;
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
