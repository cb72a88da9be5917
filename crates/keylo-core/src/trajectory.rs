//! Poses and trajectories.

use nalgebra::Isometry3;

/// A rigid-body pose: sensor frame → world frame.
pub type Pose = Isometry3<f64>;

/// Timestamped poses, in time order.
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// let mut t = Trajectory::default();
/// t.push(0.0, Pose::identity());
/// assert_eq!(t.len(), 1);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trajectory {
    pub stamps: Vec<f64>,
    pub poses: Vec<Pose>,
}

impl Trajectory {
    /// Appends a pose.
    pub fn push(&mut self, stamp: f64, pose: Pose) {
        self.stamps.push(stamp);
        self.poses.push(pose);
    }

    /// Number of poses.
    pub fn len(&self) -> usize {
        self.poses.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }

    /// Length of the path through the positions, metres.
    pub fn path_length(&self) -> f64 {
        self.poses
            .windows(2)
            .map(|w| (w[1].translation.vector - w[0].translation.vector).norm())
            .sum()
    }

    /// Iterator over `(stamp, pose)`.
    pub fn iter(&self) -> impl Iterator<Item = (f64, &Pose)> {
        self.stamps.iter().copied().zip(self.poses.iter())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn path_length_sums_steps() {
        let mut t = Trajectory::default();
        for i in 0..4 {
            let p = Pose::from_parts(
                Translation3::new(i as f64, 0.0, 0.0),
                UnitQuaternion::identity(),
            );
            t.push(i as f64, p);
        }
        assert!((t.path_length() - 3.0).abs() < 1e-12);
    }
}
