//! Localisation in a prior map: each frame registered against the fixed global cloud of a
//! saved map, from the motion model's guess, with KISS-ICP's machinery (`method = "icp"`:
//! deskew with the constant-velocity motion, double voxel downsampling, adaptive threshold,
//! point-to-point ICP with a Geman–McClure kernel) or NDT's (`method = "ndt"`: PCL's
//! `NormalDistributionsTransform` against one Gaussian per map voxel). Nothing is added to
//! the map. Each frame gets a fitness (the share of its points with a map point within
//! `fitness_distance`) and is *tracking* when the fitness reaches `min_fitness`; a frame that
//! is not tracking says so and its pose is not to be trusted. [`Localiser::set_pose`]
//! recovers from a lost state given a new pose.
//!
//! [`LocaliseRegistrar`] is the same as `[registrar] kind = "localise"`, so any front end
//! (`keylo run`, `keylo ros2`, Python, the C API) localises from a config.

mod config;
mod registrar;
mod start;

use keylo_core::voxel::{centroids, downsample};
use keylo_core::{PointCloud, Pose};
use keylo_registration::kiss_icp::deskew::deskew;
use keylo_registration::kiss_icp::icp::{align, IcpSettings};
use keylo_registration::kiss_icp::threshold::AdaptiveThreshold;
use keylo_registration::kiss_icp::voxel_map::VoxelHashMap;
use keylo_registration::ndt::{self, AlignSettings, GridSettings, NdtTarget};
use nalgebra::Point3;

pub use config::{LocaliseConfig, LocaliseMethod, LocaliseNdt};
pub use registrar::{register, LocaliseRegistrar};
pub use start::{initial_pose, pose_of_text, pose_of_values, OUTSIDE_MARGIN_M};

use crate::MapError;

/// One localised frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Localised {
    /// The sensor's pose in the map's world frame, at the scan's end.
    pub pose: Pose,
    /// Share of the registered points with a map point within `fitness_distance`.
    pub fitness: f64,
    /// `fitness ≥ min_fitness`.
    pub tracking: bool,
    pub iterations: usize,
    /// Whether the solver met its convergence rule.
    pub converged: bool,
    /// Points registered.
    pub points: usize,
}

/// The registration machinery against the fixed map.
enum Engine {
    Icp {
        threshold: AdaptiveThreshold,
        scratch: Vec<Point3<f64>>,
    },
    Ndt {
        target: Box<NdtTarget>,
        /// The map at twice the resolution: a wider basin for a frame that starts from a
        /// given pose (the first, and the first after `set_pose`).
        coarse: Box<NdtTarget>,
        solver: AlignSettings,
    },
}

/// Registers frames against a fixed map.
pub struct Localiser {
    config: LocaliseConfig,
    /// The map as a voxel hash: ICP's target and, for both methods, where the fitness looks.
    map: VoxelHashMap,
    /// Where the fitness looks instead, when `fitness_distance` exceeds `voxel_size` (a
    /// voxel hash finds every point within one voxel edge, not beyond).
    fit_map: Option<VoxelHashMap>,
    engine: Engine,
    pose: Pose,
    delta: Pose,
    /// A motion for the next frame from outside (IMU, wheels), used once.
    prior: Option<Pose>,
    /// The next frame starts from a given pose, not from a tracked one (the first frame,
    /// the first after `set_pose`).
    given: bool,
    frames: u64,
}

impl Localiser {
    /// A localiser in the map of `points` (world frame), starting at `initial` (the sensor's
    /// pose at the first frame's end, e.g. from `--initial-pose`). An error when the settings
    /// are out of range or NDT finds no usable voxel in the map.
    pub fn new(
        points: &[Point3<f64>],
        initial: Pose,
        config: LocaliseConfig,
    ) -> Result<Self, MapError> {
        let invalid = |message: String| MapError::Config {
            origin: "localise".into(),
            message,
        };
        config.check().map_err(invalid)?;
        let hash = |voxel: f64| {
            let mut map = VoxelHashMap::new(voxel, f64::INFINITY, config.max_points_per_voxel);
            map.update(points, &Pose::identity());
            map
        };
        let map = hash(config.voxel_size);
        let fit_map =
            (config.fitness_distance > config.voxel_size).then(|| hash(config.fitness_distance));
        let engine = match config.method {
            LocaliseMethod::Icp => Engine::Icp {
                threshold: Self::fresh_threshold(&config),
                scratch: Vec::new(),
            },
            LocaliseMethod::Ndt => {
                let ndt = config.ndt.as_ndt();
                let grid = ndt.grid();
                let target = NdtTarget::new(points, &grid, ndt.neighbour_search)
                    .map_err(|e| invalid(format!("the map as NDT's target: {e}")))?;
                let coarse_grid = GridSettings {
                    resolution: 2.0 * grid.resolution,
                    ..grid
                };
                let coarse = NdtTarget::new(points, &coarse_grid, ndt.neighbour_search)
                    .map_err(|e| invalid(format!("the map as NDT's coarse target: {e}")))?;
                Engine::Ndt {
                    target: Box::new(target),
                    coarse: Box::new(coarse),
                    solver: ndt.solver(),
                }
            }
        };
        Ok(Self {
            config,
            map,
            fit_map,
            engine,
            pose: initial,
            delta: Pose::identity(),
            prior: None,
            given: true,
            frames: 0,
        })
    }

    fn fresh_threshold(config: &LocaliseConfig) -> AdaptiveThreshold {
        AdaptiveThreshold::new(
            config.initial_threshold,
            config.min_motion,
            config.max_range,
        )
    }

    /// Points of the map the frames are registered against.
    pub fn map_points(&self) -> usize {
        self.map.len()
    }

    /// The settings.
    pub fn config(&self) -> &LocaliseConfig {
        &self.config
    }

    /// Recovers from a lost state: the next frame starts from `pose` (the last frame's pose
    /// becomes it; the motion model, learnt from frames that may have been lost, is
    /// forgotten).
    pub fn set_pose(&mut self, pose: Pose) {
        self.pose = pose;
        self.delta = Pose::identity();
        self.given = true;
    }

    /// Starts over at `pose` as a new localiser: motion, adaptive threshold and frame count
    /// forgotten.
    pub fn restart(&mut self, pose: Pose) {
        self.set_pose(pose);
        self.prior = None;
        self.frames = 0;
        if let Engine::Icp { threshold, .. } = &mut self.engine {
            *threshold = Self::fresh_threshold(&self.config);
        }
    }

    /// The motion from the last frame to the next (sensor frame of the last), e.g. from an
    /// IMU: the next frame's guess and deskew use it instead of constant velocity, once.
    pub fn set_motion_prior(&mut self, delta: Pose) {
        self.prior = Some(delta);
    }

    /// Localises one frame (frames in time order).
    pub fn localise(&mut self, frame: &keylo_core::LidarFrame) -> Localised {
        self.localise_cloud(&frame.to_cloud())
    }

    /// Localises one cloud (sensor frame, per-point times relative to its start when it has
    /// them; clouds in time order).
    pub fn localise_cloud(&mut self, cloud: &PointCloud) -> Localised {
        let first = self.frames == 0;
        let delta = self.prior.take().unwrap_or(self.delta);
        let mut points = cloud.points.clone();
        if let Some(times) = &cloud.times {
            deskew(&mut points, times, &delta);
        }
        let (min, max) = (self.config.min_range, self.config.max_range);
        points.retain(|p| {
            let r = p.coords.norm();
            r > min && r < max
        });
        let guess = if first { self.pose } else { self.pose * delta };
        // A frame that starts from a given pose (the first, the first after `set_pose`) does
        // not teach the motion model or the threshold: its correction is the given pose's
        // error, not motion.
        let from_given = first || self.given;
        let (source, pose, iterations, converged) = self.register(&points, &guess);
        self.given = false;
        let fitness = self.fitness(&source, &pose);
        let tracking = !source.is_empty() && fitness >= self.config.min_fitness;
        if let (Engine::Icp { threshold, .. }, true, false) =
            (&mut self.engine, tracking, from_given)
        {
            threshold.update(&(guess.inverse() * pose));
        }
        self.delta = match from_given {
            true => Pose::identity(),
            false => self.pose.inverse() * pose,
        };
        self.pose = pose;
        self.frames += 1;
        Localised {
            pose,
            fitness,
            tracking,
            iterations,
            converged,
            points: source.len(),
        }
    }

    /// Registers `points` from `guess`: (the points registered, pose, iterations, converged).
    /// An NDT that cannot start (no point near a map voxel) leaves the guess, unconverged.
    fn register(
        &mut self,
        points: &[Point3<f64>],
        guess: &Pose,
    ) -> (Vec<Point3<f64>>, Pose, usize, bool) {
        match &mut self.engine {
            Engine::Icp { threshold, scratch } => {
                let v = self.config.voxel_size;
                let source = downsample(&downsample(points, 0.5 * v), 1.5 * v);
                let sigma = threshold.threshold();
                let settings = IcpSettings {
                    max_iterations: self.config.max_iterations,
                    convergence: self.config.convergence,
                    max_distance: 3.0 * sigma,
                    kernel: sigma / 3.0,
                };
                let r = align(&source, &self.map, guess, &settings, scratch);
                (source, r.pose, r.iterations, r.converged)
            }
            Engine::Ndt {
                target,
                coarse,
                solver,
            } => {
                let v = self.config.ndt.source_voxel_size;
                let source = if v > 0.0 {
                    centroids(points, v)
                } else {
                    points.to_vec()
                };
                // From a given pose, first the coarse grid's wider basin.
                let (start, coarse_iterations) = match self.given {
                    true => match ndt::align(coarse, &source, guess, solver) {
                        Ok(r) => (r.pose, r.iterations),
                        Err(_) => (*guess, 0),
                    },
                    false => (*guess, 0),
                };
                match ndt::align(target, &source, &start, solver) {
                    Ok(r) => (
                        source,
                        r.pose,
                        coarse_iterations + r.iterations,
                        r.converged,
                    ),
                    Err(e) => {
                        // Not even the fine grid's neighbourhood is reached: the coarse
                        // step's pose is no better than the guess, which is kept.
                        tracing::debug!("localise: NDT did not start: {e}");
                        (source, *guess, coarse_iterations, false)
                    }
                }
            }
        }
    }

    fn fitness(&self, source: &[Point3<f64>], pose: &Pose) -> f64 {
        if source.is_empty() {
            return 0.0;
        }
        let d = self.config.fitness_distance;
        let map = self.fit_map.as_ref().unwrap_or(&self.map);
        let near = source
            .iter()
            .filter(|p| map.closest_neighbour_within(&(pose * *p), d).is_some())
            .count();
        near as f64 / source.len() as f64
    }
}
