//! The reference trajectory in the estimate's frame, for drawing beside it.

use keylo_core::{Pose, Trajectory};

/// At most this many poses (and the last) go in one path message, evenly picked: a long
/// trajectory would make every message large.
pub const MAX_POSES: usize = 5000;

/// The reference, moved so that its pose at `stamp` (the nearest one) is `estimate` — both
/// start together, as evo's origin alignment does. Every pose is kept; [`thinned`] picks
/// those sent. `None` when the reference is empty.
pub fn aligned(reference: &Trajectory, stamp: f64, estimate: &Pose) -> Option<Vec<(f64, Pose)>> {
    let (_, at) = reference
        .iter()
        .min_by(|a, b| (a.0 - stamp).abs().total_cmp(&(b.0 - stamp).abs()))?;
    let shift = estimate * at.inverse();
    Some(reference.iter().map(|(t, p)| (t, shift * p)).collect())
}

/// At most [`MAX_POSES`] of `poses`, evenly picked, and always the last one.
pub fn thinned(poses: &[(f64, Pose)]) -> impl Iterator<Item = &Pose> {
    let n = poses.len();
    let step = n.div_ceil(MAX_POSES).max(1);
    (poses.iter().enumerate())
        .filter(move |(i, _)| i % step == 0 || *i + 1 == n)
        .map(|(_, (_, p))| p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};

    #[test]
    fn the_reference_starts_at_the_estimate() {
        let mut r = Trajectory::default();
        for i in 0..20_000 {
            let p = Isometry3::from_parts(
                Translation3::new(10.0 + i as f64, 5.0, 0.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, 0.3),
            );
            r.push(i as f64 * 0.1, p);
        }
        let a = aligned(&r, 0.1, &Pose::identity()).unwrap();
        assert_eq!(a.len(), 20_000);
        assert_eq!(a.last().unwrap().0, 1999.9);
        assert!(a[1].1.translation.vector.norm() < 1e-9);
        // Pose 1 (stamp 0.1) is the identity; pose 0 one metre behind it along its heading.
        let back = a[0].1.translation.vector;
        assert!((back.norm() - 1.0).abs() < 1e-9, "{back}");
        assert!(aligned(&Trajectory::default(), 0.0, &Pose::identity()).is_none());
    }

    #[test]
    fn paths_are_thinned_once_to_the_limit_and_keep_their_last_pose() {
        let poses = |n: usize| -> Vec<(f64, Pose)> {
            (0..n)
                .map(|i| (i as f64, Isometry3::translation(i as f64, 0.0, 0.0)))
                .collect()
        };
        for (n, sent) in [
            (0, 0),
            (10, 10),
            (MAX_POSES, MAX_POSES),
            (MAX_POSES + 1, 2501),
            (20_000, MAX_POSES + 1),
        ] {
            let p = poses(n);
            let t: Vec<&Pose> = thinned(&p).collect();
            assert_eq!(t.len(), sent, "{n} poses");
            if n > 0 {
                assert_eq!(t.last().unwrap().translation.x, (n - 1) as f64);
            }
        }
    }
}
