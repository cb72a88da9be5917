//! Property tests: SE(3) algebra and the TUM/KITTI round trips.

use keylo_core::{Pose, Trajectory};
use keylo_eval::pose_error::{relative, relative_error, PoseRelation};
use keylo_io::trajectory::{format_kitti, format_tum, parse_kitti, parse_tum};
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;

fn pose() -> impl Strategy<Value = Pose> {
    (
        prop::array::uniform3(-3.0..3.0f64),
        prop::array::uniform3(-100.0..100.0f64),
    )
        .prop_map(|(r, t)| {
            Pose::from_parts(
                Translation3::new(t[0], t[1], t[2]),
                UnitQuaternion::from_scaled_axis(Vector3::from(r)),
            )
        })
}

fn close(a: &Pose, b: &Pose, tol_t: f64, tol_r: f64) -> bool {
    (a.translation.vector - b.translation.vector).norm() < tol_t
        && a.rotation.angle_to(&b.rotation) < tol_r
}

proptest! {
    #[test]
    fn compose_and_inverse_round_trip(a in pose(), b in pose()) {
        prop_assert!(close(&(a * b).inverse(), &(b.inverse() * a.inverse()), 1e-9, 1e-12));
        prop_assert!(close(&(a.inverse() * a), &Pose::identity(), 1e-9, 1e-12));
        prop_assert!(close(&relative(&a, &(a * b)), &b, 1e-9, 1e-12));
    }

    #[test]
    fn quaternion_matrix_round_trip(a in pose()) {
        let m = a.rotation.to_rotation_matrix();
        let back = UnitQuaternion::from_rotation_matrix(&m);
        prop_assert!(back.angle_to(&a.rotation) < 1e-12);
    }

    #[test]
    fn rpe_is_invariant_to_a_global_frame(a in pose(), b in pose(), c in pose(), d in pose(), g in pose()) {
        let e1 = relative_error(&a, &b, &c, &d);
        let e2 = relative_error(&(g * a), &(g * b), &(g * c), &(g * d));
        for rel in [PoseRelation::Translation, PoseRelation::AngleDeg] {
            prop_assert!((rel.of(&e1) - rel.of(&e2)).abs() < 1e-6);
        }
    }

    #[test]
    fn tum_round_trip(poses in prop::collection::vec(pose(), 1..8), t0 in 0.0..2e9f64) {
        let traj = Trajectory { stamps: (0..poses.len()).map(|i| t0 + i as f64 * 0.1).collect(), poses };
        let back = parse_tum(&format_tum(&traj), "mem").unwrap();
        prop_assert_eq!(back.len(), traj.len());
        for (x, y) in traj.iter().zip(back.iter()) {
            prop_assert!((x.0 - y.0).abs() < 1e-6);
            prop_assert!(close(x.1, y.1, 1e-8, 1e-8));
        }
    }

    #[test]
    fn kitti_round_trip(poses in prop::collection::vec(pose(), 1..8)) {
        let traj = Trajectory { stamps: (0..poses.len()).map(|i| i as f64).collect(), poses };
        let back = parse_kitti(&format_kitti(&traj), "mem").unwrap();
        prop_assert_eq!(&back.stamps, &traj.stamps);
        for (x, y) in traj.poses.iter().zip(&back.poses) {
            prop_assert!(close(x, y, 1e-9, 1e-11));
        }
    }
}
