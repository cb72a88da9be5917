//! A registrar of your own crate, used by keylo's pipeline like a built-in one: no plugin, no C
//! ABI. This toy aligns scan centroids (translation only); a real one would do better, the
//! wiring is the same.
//!
//! `cargo run --example custom_registrar`

use keylo::{BuildContext, CoreError, PointCloud, Pose, Registrar, Registration};
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// `[registrar] kind = "centroid"`: its parameters, documented like any backend's.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct CentroidConfig {
    /// Scale applied to the centroid shift (1 = as measured).
    pub gain: f64,
}

/// Tracks the sensor by how the scan centroid moves.
pub struct Centroid {
    gain: f64,
    first: Option<Point3<f64>>,
}

fn centroid(cloud: &PointCloud) -> Point3<f64> {
    let sum: Vector3<f64> = cloud.points.iter().map(|p| p.coords).sum();
    Point3::from(sum / cloud.len().max(1) as f64)
}

impl Registrar for Centroid {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        let c = centroid(cloud);
        let first = *self.first.get_or_insert(c);
        // The world stands still: the centroid moving by d means the sensor moved by -d.
        let pose = Pose::translation(
            self.gain * (first.x - c.x),
            self.gain * (first.y - c.y),
            self.gain * (first.z - c.z),
        );
        Ok(Registration {
            stamp: cloud.timestamp,
            pose,
            source_points: cloud.len(),
            iterations: 1,
            converged: true,
            degeneracy: None,
        })
    }

    fn map_size(&self) -> usize {
        0
    }
}

/// The built-in registry plus `centroid`.
pub fn registry() -> keylo::Registry {
    let mut registry = keylo::registry();
    registry.registrars.add::<CentroidConfig>(
        "centroid",
        "scan-centroid tracking (an example of a user-defined registrar)",
        |c: CentroidConfig, _ctx: &BuildContext| {
            let gain = if c.gain == 0.0 { 1.0 } else { c.gain };
            Ok(Box::new(Centroid { gain, first: None }))
        },
    );
    registry
}

/// Runs `toml` (any config naming `kind = "centroid"`) with the extended registry; returns
/// the x of every pose.
pub fn run(toml: &str) -> Result<Vec<f64>, CoreError> {
    let registry = registry();
    let raw = keylo::config::RawConfig::parse("custom_registrar", toml)?;
    let config = registry.resolve(&raw)?;
    let mut odometry = keylo::Odometry::build(&config, &registry)?;
    let mut xs = Vec::new();
    for k in 0..5 {
        // A wall 10 m ahead, coming 0.5 m closer every frame.
        let x = 10.0 - 0.5 * k as f64;
        let points = (0..200)
            .map(|i| Point3::new(x, f64::from(i) * 0.05 - 5.0, 0.0))
            .collect();
        let mut frame = keylo::LidarFrame::empty(
            k,
            k as f64 * 0.1,
            0,
            0,
            std::sync::Arc::new(keylo::BeamGeometry::unknown("example", 0)),
        );
        frame.scan = Some(std::sync::Arc::new(keylo::ScanPoints {
            source_index: (0..200).collect(),
            pixel: vec![keylo::ScanPoints::NONE; 200],
            points,
            ..keylo::ScanPoints::default()
        }));
        xs.push(odometry.process(&frame)?.pose.translation.x);
    }
    Ok(xs)
}

#[allow(dead_code)] // a test includes this file as a module
fn main() -> Result<(), CoreError> {
    let xs = run("[registrar]\nkind = \"centroid\"\n")?;
    println!("x per frame: {xs:?}");
    Ok(())
}
