//! Localisation in a prior map: each frame registered against the fixed global cloud of a
//! saved map with KISS-ICP's machinery (deskew with the constant-velocity motion, double voxel
//! downsampling, adaptive threshold, point-to-point ICP with a Geman–McClure kernel), from the
//! motion model's guess. Nothing is added to the map. Each frame gets a fitness (the share of
//! its points with a map point within `fitness_distance`) and is *tracking* when the fitness
//! reaches `min_fitness`; a frame that is not tracking says so and its pose is not to be
//! trusted. [`Localiser::set_pose`] recovers from a lost state given a new pose.

use keylo_core::voxel::downsample;
use keylo_core::{LidarFrame, Pose};
use keylo_registration::kiss_icp::deskew::deskew;
use keylo_registration::kiss_icp::icp::{align, IcpSettings};
use keylo_registration::kiss_icp::threshold::AdaptiveThreshold;
use keylo_registration::kiss_icp::voxel_map::VoxelHashMap;
use nalgebra::Point3;
use serde::{Deserialize, Serialize};

use crate::config::parse_table;
use crate::MapError;

/// `[localise]` settings (KISS-ICP's names and defaults where they mean the same).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct LocaliseConfig {
    /// Voxel edge of the map the frames are registered against, and of the frames' own
    /// downsampling (0.5× and 1.5×, as KISS-ICP), m.
    pub voxel_size: f64,
    /// Points kept per map voxel.
    pub max_points_per_voxel: usize,
    /// Frame points beyond this range are dropped, m.
    pub max_range: f64,
    /// Frame points nearer than this are dropped, m.
    pub min_range: f64,
    /// The adaptive correspondence threshold's start, m (KISS-ICP's).
    pub initial_threshold: f64,
    /// Motion below which the adaptive threshold does not learn from a frame, m.
    pub min_motion: f64,
    /// ICP iterations at most.
    pub max_iterations: usize,
    /// ICP has converged when its step is below this.
    pub convergence: f64,
    /// A point fits the map when a map point lies within this distance after registration, m.
    pub fitness_distance: f64,
    /// A frame is tracking when at least this share of its points fit the map.
    pub min_fitness: f64,
}

impl Default for LocaliseConfig {
    fn default() -> Self {
        Self {
            voxel_size: 1.0,
            max_points_per_voxel: 20,
            max_range: 100.0,
            min_range: 0.0,
            initial_threshold: 2.0,
            min_motion: 0.1,
            max_iterations: 500,
            convergence: 1e-4,
            fitness_distance: 0.5,
            min_fitness: 0.5,
        }
    }
}

impl LocaliseConfig {
    /// The settings of a config's `[localise]` table; the error names the key.
    pub fn from_table(table: &toml::Table, origin: &str) -> Result<Self, MapError> {
        parse_table(table, "localise", origin, Self::check)
    }

    /// Checks every value; the message names the key.
    pub fn check(&self) -> Result<(), String> {
        let positive = [
            ("voxel_size", self.voxel_size),
            ("max_range", self.max_range),
            ("initial_threshold", self.initial_threshold),
            ("convergence", self.convergence),
            ("fitness_distance", self.fitness_distance),
        ];
        for (key, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!(
                    "localise.{key} = {v}: expected a finite value above 0"
                ));
            }
        }
        if !(self.min_range.is_finite() && self.min_range >= 0.0 && self.min_range < self.max_range)
        {
            return Err(format!(
                "localise.min_range = {}: expected 0 ≤ min_range < max_range = {}",
                self.min_range, self.max_range
            ));
        }
        if !(self.min_motion.is_finite() && self.min_motion >= 0.0) {
            return Err(format!(
                "localise.min_motion = {}: expected 0 or more",
                self.min_motion
            ));
        }
        if !(0.0..=1.0).contains(&self.min_fitness) {
            return Err(format!(
                "localise.min_fitness = {}: expected 0..=1",
                self.min_fitness
            ));
        }
        if self.max_points_per_voxel == 0 || self.max_iterations == 0 {
            return Err(
                "localise.max_points_per_voxel and localise.max_iterations: expected at least 1"
                    .into(),
            );
        }
        Ok(())
    }
}

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
    /// Points registered.
    pub points: usize,
}

/// Registers frames against a fixed map.
pub struct Localiser {
    config: LocaliseConfig,
    map: VoxelHashMap,
    pose: Pose,
    delta: Pose,
    threshold: AdaptiveThreshold,
    scratch: Vec<Point3<f64>>,
}

impl Localiser {
    /// A localiser in the map of `points` (world frame), starting at `initial` (the sensor's
    /// pose at the first frame's end, e.g. from `--initial-pose`).
    pub fn new(points: &[Point3<f64>], initial: Pose, config: LocaliseConfig) -> Self {
        let mut map = VoxelHashMap::new(
            config.voxel_size,
            f64::INFINITY,
            config.max_points_per_voxel,
        );
        map.update(points, &Pose::identity());
        Self {
            threshold: AdaptiveThreshold::new(
                config.initial_threshold,
                config.min_motion,
                config.max_range,
            ),
            config,
            map,
            pose: initial,
            delta: Pose::identity(),
            scratch: Vec::new(),
        }
    }

    /// Points of the map the frames are registered against.
    pub fn map_points(&self) -> usize {
        self.map.len()
    }

    /// Recovers from a lost state: the next frame starts from `pose` (the last frame's pose
    /// becomes it; the motion model is forgotten).
    pub fn set_pose(&mut self, pose: Pose) {
        self.pose = pose;
        self.delta = Pose::identity();
    }

    /// Localises one frame (frames in time order).
    pub fn localise(&mut self, frame: &LidarFrame, first: bool) -> Localised {
        let cloud = frame.to_cloud();
        let mut points = cloud.points;
        if let Some(times) = &cloud.times {
            deskew(&mut points, times, &self.delta);
        }
        let (min, max) = (self.config.min_range, self.config.max_range);
        points.retain(|p| {
            let r = p.coords.norm();
            r > min && r < max
        });
        let v = self.config.voxel_size;
        let source = downsample(&downsample(&points, 0.5 * v), 1.5 * v);
        let guess = if first {
            self.pose
        } else {
            self.pose * self.delta
        };
        let sigma = self.threshold.threshold();
        let settings = IcpSettings {
            max_iterations: self.config.max_iterations,
            convergence: self.config.convergence,
            max_distance: 3.0 * sigma,
            kernel: sigma / 3.0,
        };
        let r = align(&source, &self.map, &guess, &settings, &mut self.scratch);
        let fitness = self.fitness(&source, &r.pose);
        let tracking = fitness >= self.config.min_fitness;
        if tracking && !first {
            self.threshold.update(&(guess.inverse() * r.pose));
        }
        if !first {
            self.delta = self.pose.inverse() * r.pose;
        }
        self.pose = r.pose;
        Localised {
            pose: r.pose,
            fitness,
            tracking,
            iterations: r.iterations,
            points: source.len(),
        }
    }

    fn fitness(&self, source: &[Point3<f64>], pose: &Pose) -> f64 {
        if source.is_empty() {
            return 0.0;
        }
        let d = self.config.fitness_distance;
        let near = source
            .iter()
            .filter(|p| self.map.closest_neighbour_within(&(pose * *p), d).is_some())
            .count();
        near as f64 / source.len() as f64
    }
}
