//! Bad input to the NDT aligner and registrar: a clear error (or a flagged frame), never a
//! panic, and an error leaves the registrar's state as it was.

use keylo_core::{PointCloud, Registrar};
use keylo_registration::ndt::{align, AlignSettings, GridSettings, NdtTarget, NeighbourSearch};
use keylo_registration::{Ndt, NdtConfig, RegistrationError};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};

/// Two walls and a floor around the origin, dense enough for 1 m voxels.
fn room(shift: f64) -> Vec<Point3<f64>> {
    let mut pts = Vec::new();
    for i in 0..80 {
        for j in 0..30 {
            let (a, b) = (f64::from(i) * 0.1 - 4.0, f64::from(j) * 0.1);
            pts.push(Point3::new(a + shift, 3.0, b - 1.0));
            pts.push(Point3::new(4.0 + shift, a, b - 1.0));
            pts.push(Point3::new(
                a + shift,
                b * 2.0 - 3.0,
                -1.5 + 0.02 * (a * 2.0).sin(),
            ));
        }
    }
    pts
}

fn modes() -> [NeighbourSearch; 3] {
    [
        NeighbourSearch::Radius,
        NeighbourSearch::Direct7,
        NeighbourSearch::Direct1,
    ]
}

#[test]
fn empty_and_tiny_targets_are_errors() {
    for search in modes() {
        let g = GridSettings::default();
        assert!(matches!(
            NdtTarget::new(&[], &g, search),
            Err(RegistrationError::BadCloud(_))
        ));
        let tiny = [Point3::new(1.0, 2.0, 3.0), Point3::new(1.1, 2.0, 3.0)];
        let e = NdtTarget::new(&tiny, &g, search).err().unwrap().to_string();
        assert!(e.contains("no voxel"), "{e}");
    }
}

#[test]
fn all_points_in_one_voxel() {
    let g = GridSettings::default();
    // Identical points: no covariance at all.
    let same = vec![Point3::new(0.5, 0.5, 0.5); 100];
    assert!(NdtTarget::new(&same, &g, NeighbourSearch::Radius).is_err());
    // A blob inside one voxel: one Gaussian; alignment runs (rank-deficient Hessian) and
    // returns a finite pose or an error, never a panic.
    let blob: Vec<Point3<f64>> = (0..200)
        .map(|i| {
            let t = f64::from(i);
            Point3::new(
                0.5 + 0.3 * (t * 0.7).sin(),
                0.5 + 0.3 * (t * 1.3).cos(),
                0.5 + 0.2 * (t * 0.3).sin(),
            )
        })
        .collect();
    for search in modes() {
        let target = NdtTarget::new(&blob, &g, search).unwrap();
        assert_eq!(target.cells().len(), 1);
        let guess = Isometry3::translation(0.05, 0.0, 0.0);
        match align(&target, &blob, &guess, &AlignSettings::default()) {
            Ok(r) => assert!(r.pose.translation.vector.iter().all(|v| v.is_finite())),
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
}

#[test]
fn non_finite_guess_and_empty_source_are_errors() {
    let target = NdtTarget::new(
        &room(0.0),
        &GridSettings::default(),
        NeighbourSearch::Radius,
    )
    .unwrap();
    let bad = Isometry3::from_parts(
        Translation3::new(f64::NAN, 0.0, 0.0),
        UnitQuaternion::identity(),
    );
    let e = align(&target, &room(0.0), &bad, &AlignSettings::default()).unwrap_err();
    assert!(matches!(e, RegistrationError::BadGuess(_)), "{e}");
    let inf = Isometry3::translation(f64::INFINITY, 0.0, 0.0);
    assert!(align(&target, &room(0.0), &inf, &AlignSettings::default()).is_err());
    let e = align(
        &target,
        &[],
        &Isometry3::identity(),
        &AlignSettings::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("empty"), "{e}");
}

#[test]
fn absurd_finite_guesses_end_without_a_panic_or_a_hang() {
    let points = room(0.0);
    for search in modes() {
        let target = NdtTarget::new(&points, &GridSettings::default(), search).unwrap();
        for guess in [
            Isometry3::translation(1e200, -1e200, 0.0),
            Isometry3::translation(3e9, 0.0, 0.0),
            Isometry3::translation(50.0, 0.0, 0.0),
        ] {
            // No overlap at all: an error naming the cause (PCL would report "converged").
            let e = align(&target, &points, &guess, &AlignSettings::default()).unwrap_err();
            assert!(e.to_string().contains("no source point"), "{e}");
        }
    }
}

#[test]
fn bad_parameters_are_rejected_when_the_registrar_is_built() {
    let bad = [
        NdtConfig {
            resolution: 0.0,
            ..NdtConfig::default()
        },
        NdtConfig {
            outlier_ratio: 1.0,
            ..NdtConfig::default()
        },
        NdtConfig {
            step_size: f64::NAN,
            ..NdtConfig::default()
        },
        NdtConfig {
            max_iterations: 0,
            ..NdtConfig::default()
        },
        NdtConfig {
            min_points_per_voxel: 2,
            ..NdtConfig::default()
        },
        NdtConfig {
            min_range: 200.0,
            ..NdtConfig::default()
        },
    ];
    for c in bad {
        let e = Ndt::new(c).err().unwrap();
        assert!(matches!(e, RegistrationError::BadParameter { .. }), "{e}");
    }
}

#[test]
fn bad_clouds_are_errors_that_keep_the_state() {
    let mut ndt = Ndt::new(NdtConfig::default()).unwrap();
    // Non-finite point.
    let mut nan = room(0.0);
    nan[7].y = f64::NAN;
    assert!(ndt.register(&PointCloud::from_points(0.0, nan)).is_err());
    // Nothing within range.
    let far = vec![Point3::new(500.0, 0.0, 0.0); 10];
    let e = ndt
        .register(&PointCloud::from_points(0.0, far))
        .unwrap_err();
    assert!(e.to_string().contains("max_range"), "{e}");
    // A first frame too small to make a map.
    let tiny = vec![Point3::new(1.0, 1.0, 1.0), Point3::new(1.2, 1.0, 1.0)];
    let e = ndt
        .register(&PointCloud::from_points(0.0, tiny))
        .unwrap_err();
    assert!(e.to_string().contains("no voxel"), "{e}");
    assert_eq!(ndt.map_size(), 0);
    // The state is untouched: a good frame now founds the map, the next one registers.
    let first = ndt
        .register(&PointCloud::from_points(0.0, room(0.0)))
        .unwrap();
    assert_eq!(first.pose, Isometry3::identity());
    assert!(ndt.map_size() > 0);
    let second = ndt
        .register(&PointCloud::from_points(0.1, room(0.0)))
        .unwrap();
    assert!(
        second.pose.translation.vector.norm() < 0.05,
        "{}",
        second.pose
    );
}

#[test]
fn divergence_beyond_the_bound_is_an_error_and_keeps_the_pose() {
    let config = NdtConfig {
        max_motion_per_frame: 0.05,
        transformation_epsilon: 1e-4,
        ..NdtConfig::default()
    };
    let mut ndt = Ndt::new(config).unwrap();
    ndt.register(&PointCloud::from_points(0.0, room(0.0)))
        .unwrap();
    // The sensor moved 0.3 m (the scene appears shifted by −0.3 m): beyond the 5 cm bound.
    let e = ndt
        .register(&PointCloud::from_points(0.1, room(-0.3)))
        .unwrap_err();
    assert!(e.to_string().contains("max_motion_per_frame"), "{e}");
    assert_eq!(ndt.pose(), Isometry3::identity());
    // Within the bound it registers.
    assert!(ndt
        .register(&PointCloud::from_points(0.2, room(-0.02)))
        .is_ok());
}
