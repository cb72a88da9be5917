//! Whole-simulator tests: determinism, ground truth, geometry, channel sanity.

use keylo_core::LidarFrame;
use parry3d::math::Vector as GVec;

use crate::sensor::SensorModel;
use crate::{Appearance, SceneKind, SensorKind, SimConfig, Simulator};
use nalgebra::Vector3;

fn sim(scene: SceneKind, seed: u64, columns: usize) -> Simulator {
    let c = SimConfig {
        scene,
        seed,
        columns,
        frames: 5,
        ..SimConfig::default()
    };
    Simulator::new(&c).unwrap()
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn same_seed_gives_identical_frames_whatever_the_threads() {
    let park_ouster = |seed| {
        Simulator::new(&SimConfig {
            scene: SceneKind::Park,
            seed,
            columns: 512,
            frames: 5,
            appearance: crate::Appearance::Ouster,
            ..SimConfig::default()
        })
        .unwrap()
    };
    let pairs = [
        (sim(SceneKind::Lab, 7, 512), sim(SceneKind::Lab, 7, 512)),
        (park_ouster(7), park_ouster(7)),
    ];
    for (a, b) in pairs {
        let fa = in_pool(1, || a.frame(2));
        let fb = in_pool(3, || b.frame(2));
        assert_eq!(fa, fb);
        let bits = |f: &LidarFrame| f.range.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&fa), bits(&fb));
    }
}

#[test]
fn different_seeds_give_different_textures() {
    let a = sim(SceneKind::Corridor, 1, 512).frame(0);
    let b = sim(SceneKind::Corridor, 2, 512).frame(0);
    let differing = a
        .reflectivity
        .iter()
        .zip(&b.reflectivity)
        .filter(|(x, y)| (**x - **y).abs() > 5.0)
        .count();
    assert!(differing > a.reflectivity.len() / 10, "{differing}");
}

#[test]
fn ground_truth_starts_at_identity_and_is_continuous() {
    for (scene, speed) in [
        (SceneKind::Lab, 1.0),
        (SceneKind::Corridor, 1.2),
        (SceneKind::Road, 8.0),
        (SceneKind::Park, 1.4),
    ] {
        let c = SimConfig {
            scene,
            frames: 300,
            ..SimConfig::default()
        };
        let s = Simulator::new(&c).unwrap();
        let gt = s.ground_truth();
        assert_eq!(gt.len(), 300);
        assert_eq!(gt.poses[0], keylo_core::Pose::identity());
        assert!((gt.stamps[0] - 0.1 * 1023.0 / 1024.0).abs() < 1e-12);
        let ramp_frames = (c.start_ramp_s / 0.1) as usize;
        for (k, w) in gt.poses.windows(2).enumerate() {
            let step = (w[1].translation.vector - w[0].translation.vector).norm();
            if k < ramp_frames {
                // Accelerating from rest: slower than cruise, never faster.
                assert!(step < speed * 0.1 * 1.02, "{scene:?} {k}: {step}");
                continue;
            }
            assert!(
                (step - speed * 0.1).abs() < 0.02 * speed,
                "{scene:?} {k}: {step}"
            );
            let turn = w[0].rotation.angle_to(&w[1].rotation);
            assert!(turn < 0.1, "{scene:?} {k}: {turn}");
            assert!((gt.stamps[k + 1] - gt.stamps[k] - 0.1).abs() < 1e-9);
        }
    }
}

#[test]
fn points_lie_on_scene_surfaces() {
    for (scene, min_checked) in [(SceneKind::Lab, 5000), (SceneKind::Park, 2500)] {
        check_points_on_surfaces(scene, Appearance::Ideal, 1.0, min_checked);
    }
}

/// With staggered beams (the `ouster` OS0-128) every pixel's point, placed by the pose at
/// the pixel's own firing time, still lies on the scene, and its range runs through the beam
/// origin (27 mm out). Fast (5 m/s), so that the column's time instead of the pixel's would
/// put points centimetres off.
#[test]
fn staggered_points_lie_on_scene_surfaces_at_their_own_firing_time() {
    check_points_on_surfaces(SceneKind::Lab, Appearance::Ouster, 5.0, 5000);
}

/// Pixel `i`'s beam origin and direction (sensor frame) from the frame's beam geometry alone:
/// the column it fired in, that column's azimuth, the beam's offsets.
fn beam_ray(
    f: &keylo_core::LidarFrame,
    sensor: &SensorModel,
    i: usize,
    origin: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let (r, c) = (i / f.cols, i % f.cols);
    let lag = f.beams.column_lag_by_row.get(r).copied().unwrap_or(0);
    let encoder = sensor.azimuth_rad((c + f.cols - lag) % f.cols);
    let az = encoder - f.beams.azimuth_deg[r].to_radians();
    let alt = f.beams.altitude_deg[r].to_radians();
    let start = Vector3::new(encoder.cos(), encoder.sin(), 0.0) * origin;
    let dir = Vector3::new(alt.cos() * az.cos(), alt.cos() * az.sin(), alt.sin());
    (start, dir)
}

fn check_points_on_surfaces(scene: SceneKind, look: Appearance, speed: f64, min_checked: usize) {
    let c = SimConfig {
        scene,
        range_noise_m: 0.0,
        frames: 1,
        appearance: look,
        speed_scale: speed,
        ..SimConfig::default()
    };
    let s = Simulator::new(&c).unwrap();
    let f = s.frame(0);
    let origin = f.beams.origin_to_beam_mm * 1e-3;
    assert_eq!(origin > 0.0, look == Appearance::Ouster);
    let mut checked = 0;
    for i in (0..f.rows * f.cols).step_by(13).filter(|&i| f.valid[i]) {
        let pose = s.pose_at(f.pixel_time(i));
        let p = pose * f.points[i].cast::<f64>();
        let d = s
            .scene()
            .world
            .surface_distance(GVec::new(p.x as f32, p.y as f32, p.z as f32));
        assert!(
            d < 2e-3,
            "{scene:?} {look:?} pixel {i}: {d} m off the surfaces"
        );
        // The frame's beam geometry describes the ray: from the beam origin on the fired
        // column's azimuth, along that azimuth minus the beam's offset, `range - origin` long.
        let (start, dir) = beam_ray(&f, s.sensor(), i, origin);
        let q = f.points[i].cast::<f64>().coords;
        let along = q - start;
        assert!((along.norm() - (f64::from(f.range[i]) - origin)).abs() < 1e-4);
        assert!(along.normalize().dot(&dir) > 1.0 - 1e-9, "pixel {i}");
        checked += 1;
    }
    assert!(checked > min_checked, "{scene:?}: {checked}");
}

#[test]
fn beams_at_known_surfaces_give_the_known_range() {
    // A static sensor in the corridor at (4, -0.55, ~1.5): the horizontal beam to the right
    // (column 3W/4) hits the wall y = -1.2, the lowest forward beam the floor z = 0.
    let c = SimConfig {
        scene: SceneKind::Corridor,
        sensor: SensorKind::Os1_64,
        range_noise_m: 0.0,
        speed_scale: 0.0,
        frames: 1,
        ..SimConfig::default()
    };
    let s = Simulator::new(&c).unwrap();
    let f = s.frame(0);
    let right = (32, 3 * f.cols / 4, 1, -1.2);
    let floor = (63, f.cols / 2, 2, 0.0);
    for (row, col, axis, plane) in [right, floor] {
        let i = row * f.cols + col;
        assert!(f.valid[i]);
        // Static but swaying: the attitude at the column's firing time matters.
        let pose = s.pose_at(f.column_times[col]);
        let o = pose.translation.vector;
        assert!((o.x - 4.0).abs() < 1e-9 && (o.y + 0.55).abs() < 1e-9);
        let dir = pose.rotation * s.sensor().direction(row, col);
        let expected = (plane - o[axis]) / dir[axis];
        assert!(expected > 0.0);
        assert!(
            (f64::from(f.range[i]) - expected).abs() < 1e-3,
            "{} vs {expected}",
            f.range[i]
        );
        let p = pose * f.points[i].cast::<f64>();
        assert!((p[axis] - plane).abs() < 1e-3, "{p:?}");
    }
}

#[test]
fn without_motion_distortion_column_times_are_equal() {
    let c = SimConfig {
        motion_distortion: false,
        frames: 3,
        columns: 512,
        ..SimConfig::default()
    };
    let s = Simulator::new(&c).unwrap();
    let f = s.frame(2);
    assert!(f.column_times.iter().all(|&t| t == f.timestamp));
    assert!((f.timestamp - 0.2).abs() < 1e-12);
    assert_eq!(s.ground_truth().stamps[2], f.timestamp);
    let moving = Simulator::new(&SimConfig {
        motion_distortion: true,
        ..c
    })
    .unwrap()
    .frame(2);
    assert!((moving.column_times[511] - (0.2 + 0.1 * 511.0 / 512.0)).abs() < 1e-12);
    assert_ne!(moving.range, f.range);
}

fn check_channels(f: &LidarFrame, max_range: f32) {
    assert!(f.check_shape().is_ok());
    for i in 0..f.rows * f.cols {
        assert!((0.0..=255.0).contains(&f.reflectivity[i]));
        assert!(f.signal[i] >= 0.0 && f.near_ir[i] >= 0.0);
        if f.valid[i] {
            assert!((0.3..=max_range).contains(&f.range[i]), "{}", f.range[i]);
        } else {
            assert_eq!((f.range[i], f.signal[i]), (0.0, 0.0));
        }
    }
}

#[test]
fn channels_are_sane_and_scenes_mostly_valid() {
    let cases = [
        (SceneKind::Lab, SensorKind::Os0_128, 0.9),
        (SceneKind::Corridor, SensorKind::Os0_128, 0.8),
        (SceneKind::Road, SensorKind::Os0_128, 0.3),
        (SceneKind::Lab, SensorKind::Os1_64, 0.9),
        (SceneKind::Corridor, SensorKind::Os1_64, 0.8),
        (SceneKind::Road, SensorKind::Os1_64, 0.3),
        (SceneKind::Park, SensorKind::Os0_128, 0.4),
    ];
    for (scene, sensor, min_fraction) in cases {
        let c = SimConfig {
            scene,
            sensor,
            frames: 1,
            ..SimConfig::default()
        };
        let s = Simulator::new(&c).unwrap();
        let f = s.frame(0);
        check_channels(&f, s.sensor().max_range_m as f32);
        let fraction = f.valid_count() as f64 / (f.rows * f.cols) as f64;
        println!("{scene:?} {sensor:?}: valid fraction {fraction:.3}");
        assert!(fraction > min_fraction, "{scene:?} {sensor:?}: {fraction}");
    }
}

#[test]
fn simulator_and_source_can_cross_threads() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<Simulator>();
    assert_send_sync::<crate::SimSource>();
}
