//! Helpers shared by the cross-crate tests.

use keylo::config::{PipelineConfig, RawConfig};
use keylo::map::{Map, MapBuilder, MapConfig};
use keylo::sim::Simulator;

/// The config `text` resolved, with the registry (every built-in backend) it was resolved by.
pub fn resolve(text: &str) -> (keylo::Registry, PipelineConfig) {
    let registry = keylo::registry();
    let config = registry
        .resolve(&RawConfig::parse("test", text).unwrap())
        .unwrap();
    (registry, config)
}

/// Runs raw KISS-ICP on the simulated frames, saving a map with `settings`; with `truth`
/// the map takes the ground-truth poses instead of the odometry's.
#[allow(dead_code)] // not every test file saves maps
pub fn mapped(sim: &Simulator, settings: MapConfig, dir: &std::path::Path, truth: bool) -> Map {
    let (registry, config) = resolve("[registrar]\nkind = \"kiss-icp\"\n");
    let mut odometry = keylo::Odometry::build(&config, &registry).unwrap();
    let mut builder = MapBuilder::create(dir, settings, "simulated road").unwrap();
    for k in 0..sim.len() {
        let frame = sim.frame(k);
        let (mut r, f) = odometry.process_guarded(&frame, true).unwrap();
        if truth {
            r.pose = sim.relative_pose_at(sim.gt_stamp(k));
        }
        builder.add(&frame, &r, f.as_ref()).unwrap();
    }
    let manifest = builder.finish().unwrap();
    assert_eq!(manifest.frames, sim.len());
    Map::open(dir).unwrap()
}
