//! Property tests: Umeyama alignment recovers known transforms.

use keylo_eval::align::{umeyama, Alignment};
use nalgebra::{Matrix3, Point3, UnitQuaternion, Vector3};
use proptest::prelude::*;

fn points() -> impl Strategy<Value = Vec<Point3<f64>>> {
    prop::collection::vec(prop::array::uniform3(-10.0..10.0f64), 6..40)
        .prop_map(|v| v.into_iter().map(Point3::from).collect())
}

fn similarity(scale: f64) -> impl Strategy<Value = Alignment> {
    (
        prop::array::uniform3(-3.0..3.0f64),
        prop::array::uniform3(-50.0..50.0f64),
    )
        .prop_map(move |(r, t)| {
            Alignment::new(
                UnitQuaternion::from_scaled_axis(Vector3::from(r)),
                Vector3::from(t),
                scale,
            )
        })
}

/// True when the points spread in at least two directions (second singular value ≥ 1).
fn well_spread(x: &[Point3<f64>]) -> bool {
    let mean = x.iter().map(|p| p.coords).sum::<Vector3<f64>>() / x.len() as f64;
    let cov: Matrix3<f64> = x
        .iter()
        .map(|p| (p.coords - mean) * (p.coords - mean).transpose())
        .sum();
    let mut s: Vec<f64> = cov.singular_values().iter().copied().collect();
    s.sort_by(|a, b| b.total_cmp(a));
    s[1] / x.len() as f64 >= 1.0
}

proptest! {
    #[test]
    fn rigid_transform_is_recovered(x in points(), truth in similarity(1.0)) {
        prop_assume!(well_spread(&x));
        let y: Vec<_> = x.iter().map(|p| truth.transform_point(p)).collect();
        let a = umeyama(&x, &y, false).unwrap();
        prop_assert!(a.rotation.angle_to(&truth.rotation) < 1e-9);
        prop_assert!((a.translation - truth.translation).norm() < 1e-9);
        prop_assert_eq!(a.scale, 1.0);
    }

    #[test]
    fn noisy_transform_is_close(x in points(), truth in similarity(1.0), noise in prop::collection::vec(prop::array::uniform3(-0.01..0.01f64), 40)) {
        prop_assume!(well_spread(&x));
        let y: Vec<_> = x.iter().zip(&noise).map(|(p, n)| truth.transform_point(p) + Vector3::from(*n)).collect();
        let a = umeyama(&x, &y, false).unwrap();
        prop_assert!(a.rotation.angle_to(&truth.rotation) < 0.01);
        prop_assert!((a.translation - truth.translation).norm() < 0.1);
    }

    #[test]
    fn similarity_scale_is_recovered(x in points(), scale in 0.2..5.0f64, r in prop::array::uniform3(-3.0..3.0f64)) {
        prop_assume!(well_spread(&x));
        let truth = Alignment::new(UnitQuaternion::from_scaled_axis(Vector3::from(r)), Vector3::new(1.0, -2.0, 3.0), scale);
        let y: Vec<_> = x.iter().map(|p| truth.transform_point(p)).collect();
        let a = umeyama(&x, &y, true).unwrap();
        prop_assert!((a.scale - scale).abs() < 1e-9 * scale);
        prop_assert!(a.rotation.angle_to(&truth.rotation) < 1e-9);
        prop_assert!((a.translation - truth.translation).norm() < 1e-9);
    }
}
