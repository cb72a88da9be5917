//! The local map of recent keyframes (simple_ndt_slam's `ndt_mapping`, bounded): a frame
//! becomes a keyframe after enough motion, the map holds the last N keyframes (each
//! voxel-filtered, world frame) and the NDT target is rebuilt when it changes.

use std::collections::VecDeque;

use nalgebra::{Isometry3, Point3};

use super::neighbours::{NdtTarget, NeighbourSearch};
use super::voxel_grid::GridSettings;
use crate::{voxel, RegistrationError};

/// When a frame becomes a keyframe and how the map is kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapSettings {
    /// Translation from the last keyframe that makes a keyframe (m).
    pub keyframe_distance: f64,
    /// Rotation from the last keyframe that makes a keyframe (radians).
    pub keyframe_angle: f64,
    /// Keyframes kept.
    pub keyframes: usize,
    /// Centroid filter of a keyframe's points (m); 0 = none.
    pub voxel_size: f64,
}

/// Keyframes and the NDT target built from them.
pub struct LocalMap {
    settings: MapSettings,
    grid: GridSettings,
    search: NeighbourSearch,
    keyframes: VecDeque<Vec<Point3<f64>>>,
    last_keyframe: Option<Isometry3<f64>>,
    target: Option<NdtTarget>,
    points: usize,
}

impl LocalMap {
    /// An empty map.
    pub fn new(settings: MapSettings, grid: GridSettings, search: NeighbourSearch) -> Self {
        Self {
            settings,
            grid,
            search,
            keyframes: VecDeque::new(),
            last_keyframe: None,
            target: None,
            points: 0,
        }
    }

    /// The NDT target, once a keyframe exists.
    pub fn target(&self) -> Option<&NdtTarget> {
        self.target.as_ref()
    }

    /// The keyframes' points, world frame.
    pub fn points(&self) -> Vec<Point3<f64>> {
        self.keyframes.iter().flatten().copied().collect()
    }

    /// Points in the map.
    pub fn len(&self) -> usize {
        self.points
    }

    /// True before the first keyframe.
    pub fn is_empty(&self) -> bool {
        self.points == 0
    }

    /// Whether a frame at `pose` should become a keyframe.
    pub fn wants_keyframe(&self, pose: &Isometry3<f64>) -> bool {
        let Some(last) = self.last_keyframe else {
            return true;
        };
        let d = last.inverse() * pose;
        d.translation.vector.norm() >= self.settings.keyframe_distance
            || d.rotation.angle() >= self.settings.keyframe_angle
    }

    /// Adds the frame `points` (sensor frame) at `pose`; the map is unchanged on error (a map
    /// without any usable voxel).
    pub fn add_keyframe(
        &mut self,
        points: &[Point3<f64>],
        pose: &Isometry3<f64>,
    ) -> Result<(), RegistrationError> {
        let world: Vec<Point3<f64>> = points.iter().map(|p| pose * p).collect();
        let world = if self.settings.voxel_size > 0.0 {
            voxel::centroids(&world, self.settings.voxel_size)
        } else {
            world
        };
        // The keyframes that stay (the oldest beyond the limit drop out) plus the new one.
        let keep = self
            .keyframes
            .len()
            .min(self.settings.keyframes.saturating_sub(1));
        let dropped = self.keyframes.len() - keep;
        let all: Vec<Point3<f64>> = self
            .keyframes
            .iter()
            .skip(dropped)
            .flatten()
            .chain(world.iter())
            .copied()
            .collect();
        let target = NdtTarget::new(&all, &self.grid, self.search)?;
        self.keyframes.drain(..dropped);
        self.keyframes.push_back(world);
        self.points = all.len();
        self.target = Some(target);
        self.last_keyframe = Some(*pose);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    fn wall() -> Vec<Point3<f64>> {
        (0..2000)
            .map(|i| {
                let (a, b) = (f64::from(i % 50) * 0.1, f64::from(i / 50) * 0.1);
                Point3::new(a, 3.0 + 0.05 * (a * 3.0).sin(), b)
            })
            .collect()
    }

    fn map(keyframes: usize) -> LocalMap {
        LocalMap::new(
            MapSettings {
                keyframe_distance: 1.0,
                keyframe_angle: 0.2,
                keyframes,
                voxel_size: 0.0,
            },
            GridSettings::default(),
            NeighbourSearch::Radius,
        )
    }

    #[test]
    fn keyframes_follow_distance_and_angle_and_the_oldest_is_dropped() {
        let mut m = map(2);
        let at = |x: f64| {
            Isometry3::from_parts(Translation3::new(x, 0.0, 0.0), UnitQuaternion::identity())
        };
        assert!(m.wants_keyframe(&at(0.0)));
        m.add_keyframe(&wall(), &at(0.0)).unwrap();
        assert!(!m.wants_keyframe(&at(0.5)));
        assert!(m.wants_keyframe(&at(1.0)));
        let turned = Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 0.3),
        );
        assert!(m.wants_keyframe(&turned));
        m.add_keyframe(&wall(), &at(1.0)).unwrap();
        m.add_keyframe(&wall(), &at(2.0)).unwrap();
        assert_eq!(m.len(), 2 * wall().len());
    }

    #[test]
    fn a_map_without_usable_voxels_is_an_error_and_keeps_the_state() {
        let mut m = map(3);
        let few = vec![Point3::new(1.0, 2.0, 3.0); 4];
        assert!(m.add_keyframe(&few, &Isometry3::identity()).is_err());
        assert!(m.is_empty() && m.target().is_none());
        assert!(m.wants_keyframe(&Isometry3::identity()));
    }
}
