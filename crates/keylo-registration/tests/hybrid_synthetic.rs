//! The hybrid registrar on synthetic scenes: a corridor (degenerate along x) with textured
//! landmarks seen as described keypoints, and a closed room without keypoints.

use keylo_core::{
    DescriptorData, Descriptors, FrameKeypoints, ImageKeypoints, PointCloud, Registrar,
};
use keylo_registration::{CloudResidual, Hybrid, HybridConfig, KissIcp, KissIcpConfig};
use nalgebra::{Isometry3, Point3};

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Sensor x positions: the speed alternates 0.3 / 0.9 m per frame, so the constant-velocity
/// prediction is 0.6 m off every frame.
fn positions(frames: usize) -> Vec<f64> {
    let mut x = vec![0.0];
    for k in 1..frames {
        let v = if k % 2 == 0 { 0.3 } else { 0.9 };
        x.push(x[k - 1] + v);
    }
    x
}

/// A fresh random sample of a 4 m wide, 3 m high corridor along x around `x0`, in the
/// sensor frame of a sensor at `x0`.
fn corridor_scan(x0: f64, rng: &mut Rng) -> PointCloud {
    let points = (0..6000)
        .map(|_| {
            let (x, b) = (rng.next() * 36.0 - 18.0, rng.next());
            match (rng.next() * 3.0) as u32 {
                0 => Point3::new(x, 2.0, b * 3.0 - 1.0),
                1 => Point3::new(x, -2.0, b * 3.0 - 1.0),
                _ => Point3::new(x, b * 4.0 - 2.0, -1.0),
            }
        })
        .collect();
    let _ = x0;
    PointCloud::from_points(0.0, points)
}

/// Landmarks on the walls with 32-byte descriptors.
struct Landmarks {
    points: Vec<Point3<f64>>,
    descriptors: Vec<[u8; 32]>,
}

fn landmarks(rng: &mut Rng) -> Landmarks {
    let mut points = Vec::new();
    let mut descriptors = Vec::new();
    for i in 0..400 {
        let x = -20.0 + f64::from(i) * 0.15;
        let y = if i % 2 == 0 { 2.0 } else { -2.0 };
        points.push(Point3::new(x, y, rng.next() * 3.0 - 1.0));
        let mut d = [0u8; 32];
        for b in &mut d {
            *b = (rng.next() * 256.0) as u8;
        }
        descriptors.push(d);
    }
    Landmarks {
        points,
        descriptors,
    }
}

/// The landmarks within 15 m of a sensor at `x0`, sensor frame, a few bits flipped.
fn keypoints(l: &Landmarks, x0: f64, rng: &mut Rng) -> FrameKeypoints {
    let (mut points, mut data) = (Vec::new(), Vec::new());
    for (p, d) in l.points.iter().zip(&l.descriptors) {
        if (p.x - x0).abs() > 15.0 {
            continue;
        }
        points.push(Point3::new(p.x - x0, p.y, p.z));
        let mut d = *d;
        d[(rng.next() * 32.0) as usize] ^= 1 << ((rng.next() * 8.0) as u32);
        data.extend_from_slice(&d);
    }
    let rows = points.len();
    FrameKeypoints {
        per_image: vec![ImageKeypoints {
            image: "signal".into(),
            times: vec![0.0; rows],
            points,
            descriptors: Descriptors {
                rows,
                dim: 32,
                data: DescriptorData::Binary(data),
            },
        }],
    }
}

fn icp_config() -> KissIcpConfig {
    KissIcpConfig {
        max_range: 20.0,
        voxel_size: 0.3,
        deskew: false,
        initial_threshold: 0.5,
        ..KissIcpConfig::default()
    }
}

/// Poses of hybrid (with keypoints, `config` with the test's ICP settings) and plain
/// KISS-ICP, and the truth.
fn corridor_run_with(
    frames: usize,
    seed: u64,
    config: HybridConfig,
) -> (Vec<Isometry3<f64>>, Vec<Isometry3<f64>>, Vec<f64>) {
    let truth = positions(frames);
    let mut rng = Rng(seed);
    let marks = landmarks(&mut rng);
    let mut hybrid = Hybrid::new(HybridConfig {
        icp: icp_config(),
        ..config
    })
    .unwrap();
    let mut kiss = KissIcp::new(icp_config()).unwrap();
    let (mut h, mut k) = (Vec::new(), Vec::new());
    for &x in &truth {
        let cloud = corridor_scan(x, &mut rng);
        let kp = keypoints(&marks, x, &mut rng);
        h.push(hybrid.register_with_keypoints(&cloud, &kp).unwrap().pose);
        k.push(kiss.register(&cloud).unwrap().pose);
    }
    (h, k, truth)
}

/// The first hybrid: point-to-point cloud, equal pair weights, weight 10, no gate.
fn point_to_point_config() -> HybridConfig {
    HybridConfig {
        cloud_residual: CloudResidual::PointToPoint,
        keypoint_weight: 10.0,
        keypoint_sigma_azimuth: 0.0,
        keypoint_gate: 0.0,
        ..HybridConfig::default()
    }
}

fn corridor_run(frames: usize, seed: u64) -> (Vec<Isometry3<f64>>, Vec<Isometry3<f64>>, Vec<f64>) {
    corridor_run_with(frames, seed, point_to_point_config())
}

#[test]
fn point_to_plane_cloud_leaves_the_axis_to_the_keypoints() {
    // The defaults: point-to-plane, pairs weighted by their points' covariances, gated.
    let (h, _, truth) = corridor_run_with(12, 1, HybridConfig::default());
    for (k, (p, x)) in h.iter().zip(&truth).enumerate() {
        let err = (p.translation.x - x).abs();
        assert!(err < 0.05, "frame {k}: x error {err:.3} m");
        assert!(p.translation.vector.yz().norm() < 0.05, "{p}");
    }
}

#[test]
fn keypoints_recover_the_motion_along_the_corridor() {
    let (h, k, truth) = corridor_run(12, 1);
    let last = truth.len() - 1;
    let h_err = (h[last].translation.x - truth[last]).abs();
    let k_err = (k[last].translation.x - truth[last]).abs();
    assert!(h_err < 0.05, "hybrid x error {h_err:.3} m");
    assert!(
        k_err > 0.5,
        "kiss-icp x error {k_err:.3} m: the scene is not degenerate"
    );
    for p in &h {
        assert!(p.translation.vector.yz().norm() < 0.05, "{p}");
    }
}

#[test]
fn runs_are_bit_identical() {
    let (a, _, _) = corridor_run(6, 2);
    let (b, _, _) = corridor_run(6, 2);
    assert_eq!(a, b);
}

/// A closed room, sampled afresh every frame.
fn room_scan(sensor: &Isometry3<f64>, rng: &mut Rng) -> PointCloud {
    let points = (0..6000)
        .map(|_| {
            let (a, b) = (rng.next(), rng.next());
            let p = match (rng.next() * 6.0) as u32 {
                0 => Point3::new(a * 10.0 - 5.0, 4.0, b * 3.0 - 1.0),
                1 => Point3::new(a * 10.0 - 5.0, -4.0, b * 3.0 - 1.0),
                2 => Point3::new(5.0, a * 8.0 - 4.0, b * 3.0 - 1.0),
                3 => Point3::new(-5.0, a * 8.0 - 4.0, b * 3.0 - 1.0),
                4 => Point3::new(a * 10.0 - 5.0, b * 8.0 - 4.0, -1.0),
                _ => Point3::new(a * 10.0 - 5.0, b * 8.0 - 4.0, 2.0),
            };
            sensor.inverse() * p
        })
        .collect();
    PointCloud::from_points(0.0, points)
}

#[test]
fn without_keypoints_in_a_closed_room_it_is_kiss_icp() {
    let mut rng = Rng(3);
    let mut hybrid = Hybrid::new(HybridConfig {
        icp: icp_config(),
        ..point_to_point_config()
    })
    .unwrap();
    let mut kiss = KissIcp::new(icp_config()).unwrap();
    for k in 0..8 {
        let t = f64::from(k);
        let sensor = Isometry3::new(
            nalgebra::Vector3::new(0.2 * t, 0.05 * t * t, 0.0),
            nalgebra::Vector3::new(0.0, 0.0, 0.02 * t),
        );
        let cloud = room_scan(&sensor, &mut rng);
        let h = hybrid.register(&cloud).unwrap();
        let r = kiss.register(&cloud).unwrap();
        let d = h.pose.inverse() * r.pose;
        assert!(d.translation.vector.norm() < 1e-5, "frame {k}: {d}");
        assert!(d.rotation.angle() < 1e-6, "frame {k}");
        assert!(
            h.degeneracy.as_ref().is_none_or(|d| d.weak == 0),
            "{:?}",
            h.degeneracy
        );
    }
}
