//! keylo inside your own loop: build a [`keylo::Frontend`] from typed configs, hand it your
//! point clouds one by one (here a synthetic room passing by), give a motion prior when you
//! have one (an IMU, wheels), and read the poses, the degeneracy-based covariance and the
//! local map.
//!
//! `cargo run --example embed`

use keylo::registration::KissIcpConfig;
use keylo::{Frontend, Pose};
use nalgebra::{Translation3, UnitQuaternion};

/// A room (three walls and a floor) seen from `x` metres along it: what a LiDAR delivers.
fn scan(x: f64) -> Vec<[f64; 3]> {
    let mut points = Vec::new();
    for i in 0..80 {
        for j in 0..25 {
            let (a, b) = (f64::from(i) * 0.2 - 8.0, f64::from(j) * 0.16);
            points.extend([[a - x, 4.0, b], [a - x, -4.0, b], [9.0 - x, a * 0.4, b]]);
            points.push([a - x, b * 2.0 - 4.0, -1.5]);
        }
    }
    points
}

/// Registers `frames` scans of a sensor moving 0.1 m per frame along x, with the true motion
/// as a prior from frame 5 on. Returns the poses.
pub fn run(frames: usize) -> Result<Vec<Pose>, keylo::Error> {
    // The same as a config file's `[registrar] kind = "kiss-icp"`, `max_range = 30.0`.
    let mut frontend = Frontend::builder()
        .registrar(&KissIcpConfig {
            max_range: 30.0,
            ..Default::default()
        })
        .build()?;
    let step = Pose::from_parts(Translation3::new(0.1, 0.0, 0.0), UnitQuaternion::identity());
    let mut poses = Vec::new();
    for k in 0..frames {
        if k >= 5 {
            frontend.set_motion_prior(&step)?;
        }
        // No per-point times here (no deskewing); pass `Some(&times)` when you have them.
        let out = frontend.push_points(0.1 * k as f64, &scan(0.1 * k as f64), None)?;
        poses.push(*out.pose());
    }
    Ok(poses)
}

#[allow(dead_code)] // a test includes this file as a module
fn main() -> Result<(), keylo::Error> {
    for (k, pose) in run(10)?.iter().enumerate() {
        let t = pose.translation.vector;
        println!("frame {k}: x {:.3} y {:.3} z {:.3}", t.x, t.y, t.z);
    }
    Ok(())
}
