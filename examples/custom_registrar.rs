//! A registrar of your own crate, used by keylo's pipeline like a built-in one (named by kind
//! in TOML, or by its typed config in code): no plugin, no C ABI. This toy aligns scan
//! centroids (translation only); a real one would do better, the wiring is the same.
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
            fit: None,
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
        <CentroidConfig as keylo::config::StageParams>::KIND,
        "scan-centroid tracking (an example of a user-defined registrar)",
        |c: CentroidConfig, _ctx: &BuildContext| {
            let gain = if c.gain == 0.0 { 1.0 } else { c.gain };
            Ok(Box::new(Centroid { gain, first: None }))
        },
    );
    registry
}

keylo::stage_params!(CentroidConfig => "centroid" as RegistrarParams);

/// Runs `toml` (any config naming `kind = "centroid"`) with the extended registry; returns
/// the x of every pose.
pub fn run(toml: &str) -> Result<Vec<f64>, keylo::Error> {
    let raw = keylo::config::RawConfig::parse("custom_registrar", toml)?;
    let frontend = keylo::Frontend::from_raw(raw, registry())?;
    walk(frontend)
}

/// The same registrar from its typed config, with no TOML at all.
pub fn run_typed(gain: f64) -> Result<Vec<f64>, keylo::Error> {
    let frontend = keylo::Frontend::builder()
        .registry(registry())
        .registrar(&CentroidConfig { gain })
        .build()?;
    walk(frontend)
}

/// Five scans of a wall 10 m ahead, coming 0.5 m closer every frame; the x of every pose.
fn walk(mut frontend: keylo::Frontend) -> Result<Vec<f64>, keylo::Error> {
    let mut xs = Vec::new();
    for k in 0..5 {
        let x = 10.0 - 0.5 * f64::from(k);
        let wall: Vec<[f64; 3]> = (0..200)
            .map(|i| [x, f64::from(i) * 0.05 - 5.0, 0.0])
            .collect();
        let out = frontend.push_points(f64::from(k) * 0.1, &wall, None)?;
        xs.push(out.pose().translation.x);
    }
    Ok(xs)
}

#[allow(dead_code)] // a test includes this file as a module
fn main() -> Result<(), keylo::Error> {
    let xs = run("[registrar]\nkind = \"centroid\"\n")?;
    println!("x per frame: {xs:?}");
    println!("gain 2, typed: {:?}", run_typed(2.0)?);
    Ok(())
}
