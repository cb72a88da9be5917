//! Bad input to the GICP aligner and registrar: a clear error naming the cause, never a panic
//! and never a NaN pose, and an error leaves the registrar's state as it was.

use keylo_core::{PointCloud, Registrar};
use keylo_registration::gicp::{align, GicpCloud, GicpMode, GicpSettings};
use keylo_registration::{Gicp, GicpConfig, RegistrationError};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};

/// Two walls and a floor around the origin.
fn room() -> Vec<Point3<f64>> {
    let mut pts = Vec::new();
    for i in 0..80 {
        for j in 0..30 {
            let (a, b) = (f64::from(i) * 0.1 - 4.0, f64::from(j) * 0.1);
            pts.push(Point3::new(a, 3.0, b - 1.0));
            pts.push(Point3::new(4.0, a, b - 1.0));
            pts.push(Point3::new(a, b * 2.0 - 3.0, -1.5 + 0.02 * (a * 2.0).sin()));
        }
    }
    pts
}

fn modes() -> [GicpConfig; 3] {
    [
        GicpConfig {
            voxel_size: 0.3,
            ..GicpConfig::default()
        },
        GicpConfig {
            voxel_size: 0.3,
            cost: keylo_registration::gicp::GicpCost::PointToPlane,
            ..GicpConfig::default()
        },
        GicpConfig {
            voxel_size: 0.3,
            mode: GicpMode::FrameToFrame,
            ..GicpConfig::default()
        },
    ]
}

#[test]
fn bad_parameters_are_rejected_naming_the_key() {
    let d = GicpConfig::default;
    let bad = [
        (
            "max_correspondence_distance",
            GicpConfig {
                max_correspondence_distance: 0.0,
                ..d()
            },
        ),
        (
            "k_correspondences",
            GicpConfig {
                k_correspondences: 2,
                ..d()
            },
        ),
        (
            "gicp_epsilon",
            GicpConfig {
                gicp_epsilon: f64::NAN,
                ..d()
            },
        ),
        (
            "gicp_epsilon",
            GicpConfig {
                gicp_epsilon: 0.0,
                ..d()
            },
        ),
        (
            "transformation_epsilon",
            GicpConfig {
                transformation_epsilon: -1.0,
                ..d()
            },
        ),
        (
            "rotation_epsilon",
            GicpConfig {
                rotation_epsilon: f64::INFINITY,
                ..d()
            },
        ),
        (
            "convergence_criterion",
            GicpConfig {
                convergence_criterion: 0.0,
                ..d()
            },
        ),
        (
            "max_iterations",
            GicpConfig {
                max_iterations: 0,
                ..d()
            },
        ),
        (
            "voxel_size",
            GicpConfig {
                voxel_size: 0.0,
                ..d()
            },
        ),
        (
            "voxel_size",
            GicpConfig {
                voxel_size: -1.0,
                mode: GicpMode::FrameToFrame,
                ..d()
            },
        ),
        (
            "max_points_per_voxel",
            GicpConfig {
                max_points_per_voxel: 0,
                ..d()
            },
        ),
        (
            "initial_threshold",
            GicpConfig {
                initial_threshold: f64::NAN,
                ..d()
            },
        ),
        (
            "min_motion_th",
            GicpConfig {
                min_motion_th: -0.1,
                ..d()
            },
        ),
        (
            "max_motion_per_frame",
            GicpConfig {
                max_motion_per_frame: f64::NAN,
                ..d()
            },
        ),
        (
            "min_range",
            GicpConfig {
                min_range: 200.0,
                ..d()
            },
        ),
    ];
    for (key, c) in bad {
        let e = Gicp::new(c).err().unwrap();
        assert!(
            matches!(e, RegistrationError::BadParameter { .. }) && e.to_string().contains(key),
            "{key}: {e}"
        );
    }
    // No filter is allowed frame to frame only.
    assert!(Gicp::new(GicpConfig {
        voxel_size: 0.0,
        mode: GicpMode::FrameToFrame,
        ..d()
    })
    .is_ok());
}

#[test]
fn bad_clouds_are_errors_that_keep_the_state() {
    for config in modes() {
        let mut g = Gicp::new(config.clone()).unwrap();
        let mut nan = room();
        nan[7].y = f64::NAN;
        assert!(g.register(&PointCloud::from_points(0.0, nan)).is_err());
        let far = vec![Point3::new(500.0, 0.0, 0.0); 10];
        let e = g.register(&PointCloud::from_points(0.0, far)).unwrap_err();
        assert!(e.to_string().contains("max_range"), "{e}");
        // One point, and three: too few for covariances.
        for n in [1, 3] {
            let tiny: Vec<Point3<f64>> = (0..n)
                .map(|i| Point3::new(1.0 + f64::from(i), 1.0, 1.0))
                .collect();
            let e = g.register(&PointCloud::from_points(0.0, tiny)).unwrap_err();
            assert!(
                e.to_string().contains("at least 6 points"),
                "{:?}: {e}",
                config.mode
            );
        }
        assert_eq!(g.map_size(), 0);
        // The state is untouched: a good frame founds the map, the next one registers.
        let first = g.register(&PointCloud::from_points(0.0, room())).unwrap();
        assert_eq!(first.pose, Isometry3::identity());
        assert!(g.map_size() > 0);
        let size = g.map_size();
        // A bad frame now changes nothing either.
        let tiny = vec![Point3::new(1.0, 1.0, 1.0); 2];
        assert!(g.register(&PointCloud::from_points(0.05, tiny)).is_err());
        assert_eq!(g.map_size(), size);
        let second = g.register(&PointCloud::from_points(0.1, room())).unwrap();
        assert!(
            second.pose.translation.vector.norm() < 1e-3,
            "{}",
            second.pose
        );
    }
}

/// A plane, a line and duplicated points: frames with directions (or everything) left
/// unconstrained give a finite pose or an error, never a NaN pose or a panic.
#[test]
fn degenerate_frames_give_finite_poses_or_errors() {
    let plane: Vec<Point3<f64>> = (0..2000)
        .map(|i| {
            Point3::new(
                f64::from(i % 50) * 0.1 - 2.5,
                f64::from(i / 50) * 0.1 - 2.0,
                -1.5,
            )
        })
        .collect();
    let line: Vec<Point3<f64>> = (0..500)
        .map(|i| Point3::new(f64::from(i) * 0.01 + 1.0, 2.0, 0.0))
        .collect();
    let same = vec![Point3::new(2.0, 1.0, 0.5); 500];
    for config in modes() {
        for (name, cloud) in [("plane", &plane), ("line", &line), ("duplicates", &same)] {
            let mut g = Gicp::new(config.clone()).unwrap();
            for k in 0..3 {
                match g.register(&PointCloud::from_points(0.1 * f64::from(k), cloud.clone())) {
                    Ok(r) => {
                        let t = r.pose.translation.vector;
                        let q = r.pose.rotation.coords;
                        assert!(
                            t.iter().chain(q.iter()).all(|v| v.is_finite()),
                            "{name} {:?}: {}",
                            config.mode,
                            r.pose
                        );
                    }
                    Err(e) => assert!(!e.to_string().is_empty()),
                }
            }
        }
    }
}

#[test]
fn non_finite_guesses_and_no_overlap_are_errors() {
    let target = GicpCloud::new(room(), 20, 1e-3).unwrap();
    let source = GicpCloud::new(room(), 20, 1e-3).unwrap();
    let s = GicpSettings::default();
    let src = (&source.cloud.points[..], &source.patches[..]);
    let nan = Isometry3::from_parts(
        Translation3::new(f64::NAN, 0.0, 0.0),
        UnitQuaternion::identity(),
    );
    let e = align(src, &target, &nan, &s).unwrap_err();
    assert!(matches!(e, RegistrationError::BadGuess(_)), "{e}");
    for far in [1e200, 3e9, 50.0] {
        let e = align(src, &target, &Isometry3::translation(far, 0.0, 0.0), &s).unwrap_err();
        assert!(e.to_string().contains("too few to register"), "{e}");
    }
    let e = GicpCloud::new(vec![Point3::origin(); 3], 20, 1e-3)
        .err()
        .unwrap();
    assert!(e.to_string().contains("at least 6 points"), "{e}");
}
