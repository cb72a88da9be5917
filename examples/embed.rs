//! keylo inside your own loop: build the per-frame stages from a config, hand them your point
//! clouds one by one (here a synthetic room passing by), give a motion prior when you have one
//! (an IMU, wheels), and read the poses.
//!
//! `cargo run --example embed`

use keylo::io::cloud::{ProjectionConfig, Projector, RawCloud, Sensor};
use keylo::{Odometry, Pose};
use nalgebra::{Translation3, UnitQuaternion};

/// A room (three walls and a floor) seen from `x` metres along it: what a LiDAR delivers.
fn scan(x: f32, stamp: f64) -> RawCloud {
    let mut points = Vec::new();
    for i in 0..80 {
        for j in 0..25 {
            let (a, b) = (i as f32 * 0.2 - 8.0, j as f32 * 0.16);
            points.extend([[a - x, 4.0, b], [a - x, -4.0, b], [9.0 - x, a * 0.4, b]]);
            points.push([a - x, b * 2.0 - 4.0, -1.5]);
        }
    }
    RawCloud {
        timestamp: stamp,
        points,
        ..RawCloud::default()
    }
}

/// Registers `frames` scans of a sensor moving 0.1 m per frame along x, with the true motion
/// as a prior from frame 5 on. Returns the poses.
pub fn run(frames: usize) -> Result<Vec<Pose>, keylo::CoreError> {
    let registry = keylo::registry();
    let raw = keylo::config::RawConfig::parse(
        "embed",
        "[registrar]\nkind = \"kiss-icp\"\nmax_range = 30.0\n",
    )?;
    let config = registry.resolve(&raw)?;
    let mut odometry = Odometry::build(&config, &registry)?;
    // Unorganised clouds become frames (every point kept); skip the image grid when no stage
    // reads it.
    let mut projector = Projector::from_config(&ProjectionConfig::default(), Sensor::Generic)
        .map_err(|m| keylo::CoreError::stage("source", m))?;
    projector.set_grid_needed(odometry.needs_grid());
    let step = Pose::from_parts(Translation3::new(0.1, 0.0, 0.0), UnitQuaternion::identity());
    let mut poses = Vec::new();
    for k in 0..frames {
        let frame = projector
            .project(&scan(0.1 * k as f32, 0.1 * k as f64), k as u64)
            .map_err(|m| keylo::CoreError::stage("source", m))?;
        if k >= 5 {
            odometry.set_motion_prior(&step)?;
        }
        poses.push(odometry.process(&frame)?.pose);
    }
    Ok(poses)
}

#[allow(dead_code)] // a test includes this file as a module
fn main() -> Result<(), keylo::CoreError> {
    for (k, pose) in run(10)?.iter().enumerate() {
        let t = pose.translation.vector;
        println!("frame {k}: x {:.3} y {:.3} z {:.3}", t.x, t.y, t.z);
    }
    Ok(())
}
