//! `[localise]` (and `[registrar] kind = "localise"`): how frames are registered against a
//! saved map, every value checked with the key named.

use keylo_registration::ndt::NeighbourSearch;
use keylo_registration::{NdtConfig, RegistrationError};
use serde::{Deserialize, Serialize};

use crate::config::parse_table;
use crate::MapError;

/// How each frame is registered against the map.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum LocaliseMethod {
    /// KISS-ICP's machinery: point-to-point ICP with a Geman–McClure kernel and the adaptive
    /// correspondence threshold, against a voxel hash of the map.
    #[default]
    Icp,
    /// NDT (PCL's `NormalDistributionsTransform` semantics) against one Gaussian per map
    /// voxel of `ndt.resolution`: the classic of map-based localisation.
    Ndt,
}

/// The NDT settings of `method = "ndt"` (PCL's names; the solver's defaults are keylo's
/// `[registrar] kind = "ndt"`'s, the grid's are for localisation: docs/maps.md).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct LocaliseNdt {
    /// NDT voxel edge of the map's Gaussians, m (PCL `setResolution`). 2 m (Autoware's
    /// localisation default) keeps a 0.3 m / 5° start in the basin outdoors; indoors 1 m is
    /// more accurate (docs/results/maps.md).
    pub resolution: f64,
    /// Longest line-search step along the normalised Newton direction (PCL `setStepSize`).
    pub step_size: f64,
    /// Stop when a Newton step's squared translation (m²) is at most this.
    pub transformation_epsilon: f64,
    /// Newton iterations per frame at most.
    pub max_iterations: usize,
    /// Share of points expected to be outliers in the Gaussian-plus-uniform score.
    pub outlier_ratio: f64,
    /// Map voxels with fewer points are not used.
    pub min_points_per_voxel: usize,
    /// Which map voxels a frame point is scored against: "radius", "direct7", "direct1".
    pub neighbour_search: NeighbourSearch,
    /// Voxel edge of the centroid filter applied to each frame before matching, m; 0: none.
    pub source_voxel_size: f64,
}

impl Default for LocaliseNdt {
    fn default() -> Self {
        let n = NdtConfig::default();
        Self {
            resolution: 2.0,
            step_size: n.step_size,
            transformation_epsilon: n.transformation_epsilon,
            max_iterations: n.max_iterations,
            outlier_ratio: n.outlier_ratio,
            min_points_per_voxel: n.min_points_per_voxel,
            neighbour_search: n.neighbour_search,
            source_voxel_size: 1.0,
        }
    }
}

impl LocaliseNdt {
    /// The same settings as a `kind = "ndt"` registrar's (for its solver and grid).
    pub fn as_ndt(&self) -> NdtConfig {
        NdtConfig {
            resolution: self.resolution,
            step_size: self.step_size,
            transformation_epsilon: self.transformation_epsilon,
            max_iterations: self.max_iterations,
            outlier_ratio: self.outlier_ratio,
            min_points_per_voxel: self.min_points_per_voxel,
            neighbour_search: self.neighbour_search,
            source_voxel_size: self.source_voxel_size,
            ..NdtConfig::default()
        }
    }
}

/// `[localise]` settings (KISS-ICP's names and defaults where they mean the same); the same
/// keys as `[registrar] kind = "localise"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct LocaliseConfig {
    /// The map folder (`keylo run … --map-out DIR`), relative to the config's folder. `keylo
    /// localise MAP` names it on the command line; the `localise` registrar needs it here.
    pub map: String,
    /// The sensor's pose in the map at the first frame's end, [x, y, z, qx, qy, qz, qw];
    /// empty: the map's first keyframe (`--initial-pose` overrides it).
    pub initial_pose: Vec<f64>,
    /// Registration against the map: "icp" (KISS-ICP's machinery) or "ndt".
    pub method: LocaliseMethod,
    /// Voxel edge of the map the frames are registered against (ICP), of the frames' own
    /// downsampling (0.5× and 1.5×, as KISS-ICP; ICP) and of the voxel hash the fitness is
    /// computed in (both methods), m.
    pub voxel_size: f64,
    /// Points kept per map voxel.
    pub max_points_per_voxel: usize,
    /// Frame points beyond this range are dropped, m.
    pub max_range: f64,
    /// Frame points nearer than this are dropped, m.
    pub min_range: f64,
    /// The adaptive correspondence threshold's start, m (KISS-ICP's; ICP).
    pub initial_threshold: f64,
    /// Motion below which the adaptive threshold does not learn from a frame, m (ICP).
    pub min_motion: f64,
    /// ICP iterations at most.
    pub max_iterations: usize,
    /// ICP has converged when its step is below this.
    pub convergence: f64,
    /// A point fits the map when a map point lies within this distance after registration,
    /// m.
    pub fitness_distance: f64,
    /// A frame is tracking when at least this share of its points fit the map. Tracked
    /// frames measured 0.99 and more (simulated lab and road, another run through a changed
    /// room; real KITTI scans), a pose 3 m off in the lab 0.50 (floor and ceiling fit
    /// anywhere): 0.8 leaves room for a changed scene and refuses such poses.
    pub min_fitness: f64,
    /// NDT's settings (`method = "ndt"`).
    pub ndt: LocaliseNdt,
}

impl Default for LocaliseConfig {
    fn default() -> Self {
        Self {
            map: String::new(),
            initial_pose: Vec::new(),
            method: LocaliseMethod::Icp,
            voxel_size: 1.0,
            max_points_per_voxel: 20,
            max_range: 100.0,
            min_range: 0.0,
            initial_threshold: 2.0,
            min_motion: 0.1,
            max_iterations: 500,
            convergence: 1e-4,
            fitness_distance: 0.5,
            min_fitness: 0.8,
            ndt: LocaliseNdt::default(),
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
        if !self.initial_pose.is_empty() {
            super::start::pose_of_values(&self.initial_pose)
                .map_err(|e| format!("localise.initial_pose: {e}"))?;
        }
        if !(self.ndt.source_voxel_size.is_finite() && self.ndt.source_voxel_size >= 0.0) {
            return Err(format!(
                "localise.ndt.source_voxel_size = {}: expected 0 (none) or more",
                self.ndt.source_voxel_size
            ));
        }
        match self.ndt.as_ndt().validate() {
            Err(RegistrationError::BadParameter {
                field,
                value,
                expected,
            }) => Err(format!("localise.ndt.{field} = {value}: {expected}")),
            Err(e) => Err(format!("localise.ndt: {e}")),
            Ok(()) => Ok(()),
        }
    }
}
