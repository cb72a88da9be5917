//! Deskewing a motion-distorted simulated scan with the true frame-to-frame motion brings it
//! closer to the scene than leaving it distorted; the inverse motion makes it worse. This pins
//! the deskew convention (scan expressed at its last column) to the simulator's ground truth.

use keylo::registration::kiss_icp::deskew::deskew;
use keylo::sim::{SceneKind, SimConfig, Simulator};
use nalgebra::{Isometry3, Point3};

/// Mean distance from a sample of `b` to the nearest of a sample of `a` (brute force).
fn mean_nearest(a: &[Point3<f64>], b: &[Point3<f64>]) -> f64 {
    let sa: Vec<_> = a.iter().step_by(7).collect();
    let sb: Vec<_> = b.iter().step_by(997).collect();
    let sum: f64 = sb
        .iter()
        .map(|q| sa.iter().map(|p| (*p - *q).norm()).fold(f64::MAX, f64::min))
        .sum();
    sum / sb.len() as f64
}

#[test]
fn deskew_with_true_motion_reduces_distortion() {
    let base = SimConfig {
        scene: SceneKind::Road,
        frames: 150,
        range_noise_m: 0.0,
        ..SimConfig::default()
    };
    let sim = Simulator::new(&base).unwrap();
    let gt = sim.ground_truth();
    let undistorted = Simulator::new(&SimConfig {
        motion_distortion: false,
        ..base.clone()
    })
    .unwrap();
    let und_gt = undistorted.ground_truth();
    for k in [20usize, 140] {
        let reference_pose = undistorted.pose_at(und_gt.stamps[k]);
        let reference: Vec<_> = undistorted
            .frame(k)
            .to_cloud()
            .points
            .iter()
            .map(|p| reference_pose * p)
            .collect();
        let scan = sim.frame(k).to_cloud();
        let times = scan.times.clone().unwrap();
        let world = sim.pose_at(gt.stamps[k]);
        let in_world = |motion: Option<Isometry3<f64>>| {
            let mut pts = scan.points.clone();
            if let Some(m) = motion {
                deskew(&mut pts, &times, &m);
            }
            let pts: Vec<_> = pts.iter().map(|p| world * p).collect();
            mean_nearest(&reference, &pts)
        };
        let delta = gt.poses[k - 1].inverse() * gt.poses[k];
        let (raw, fixed, wrong) = (
            in_world(None),
            in_world(Some(delta)),
            in_world(Some(delta.inverse())),
        );
        assert!(
            fixed < 0.85 * raw,
            "frame {k}: deskewed {fixed:.4} vs raw {raw:.4}"
        );
        assert!(
            wrong > raw,
            "frame {k}: inverse motion {wrong:.4} vs raw {raw:.4}"
        );
    }
}
