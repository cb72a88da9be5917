//! The reference trajectory in the estimate's frame, for drawing beside it.

use keylo_core::{Pose, Trajectory};

/// At most this many reference poses are sent (evenly picked): a long reference would make
/// every trajectory message large.
pub const MAX_POSES: usize = 5000;

/// The reference, moved so that its pose at `stamp` (the nearest one) is `estimate` — both
/// start together, as evo's origin alignment does — and thinned to [`MAX_POSES`]. `None` when
/// the reference is empty.
pub fn aligned(reference: &Trajectory, stamp: f64, estimate: &Pose) -> Option<Vec<(f64, Pose)>> {
    let (_, at) = reference
        .iter()
        .min_by(|a, b| (a.0 - stamp).abs().total_cmp(&(b.0 - stamp).abs()))?;
    let shift = estimate * at.inverse();
    let n = reference.len();
    let step = n.div_ceil(MAX_POSES).max(1);
    Some(
        reference
            .iter()
            .enumerate()
            .filter(|(i, _)| i % step == 0 || *i + 1 == n)
            .map(|(_, (t, p))| (t, shift * p))
            .collect(),
    )
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
        assert!(a.len() <= MAX_POSES + 1);
        assert_eq!(a.last().unwrap().0, 1999.9);
        // Pose 1 (stamp 0.1) is the identity; pose 0 one metre behind it along its heading.
        let back = a[0].1.translation.vector;
        assert!((back.norm() - 1.0).abs() < 1e-9, "{back}");
        assert!(aligned(&Trajectory::default(), 0.0, &Pose::identity()).is_none());
    }
}
