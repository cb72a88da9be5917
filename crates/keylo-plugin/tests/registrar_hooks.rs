//! The SLAM hooks through the plugin C ABI (version 3): a Rust registrar exported with
//! `export_plugin!` gets keylo's motion prior, pose, reset and local-map calls through the C
//! function pointers; a version-2 table (no hooks, the shorter kind layout) still loads and
//! its hooks are errors saying it does not offer them.

use std::path::Path;
use std::sync::Arc;

use keylo_core::{CoreError, PointCloud, Pose, Registrar, Registration, Registry};
use keylo_plugin::abi::*;
use keylo_plugin::host::{register_plugin, KindV2, Plugin};
use keylo_plugin::FromConfig;
use nalgebra::Point3;
use serde::Deserialize;

#[derive(Default, Deserialize)]
struct Params {}

/// Moves by the prior when it has one, else stands still; its map is the last cloud, placed.
#[derive(Default)]
struct Follower {
    pose: Pose,
    prior: Option<Pose>,
    map: Vec<Point3<f64>>,
}

impl FromConfig for Follower {
    type Params = Params;
    fn from_params(_: Params) -> Result<Self, String> {
        Ok(Self::default())
    }
}

impl Registrar for Follower {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        if let Some(delta) = self.prior.take() {
            self.pose *= delta;
        }
        self.map = cloud.points.iter().map(|p| self.pose * p).collect();
        Ok(Registration {
            stamp: cloud.timestamp,
            pose: self.pose,
            source_points: cloud.len(),
            iterations: 1,
            converged: true,
            degeneracy: None,
            fit: None,
        })
    }

    fn map_size(&self) -> usize {
        self.map.len()
    }

    fn set_motion_prior(&mut self, delta: &Pose) -> Result<(), CoreError> {
        self.prior = Some(*delta);
        Ok(())
    }

    fn set_pose(&mut self, pose: &Pose) -> Result<(), CoreError> {
        self.pose = *pose;
        Ok(())
    }

    fn reset(&mut self) -> Result<(), CoreError> {
        *self = Self::default();
        Ok(())
    }

    fn local_map(&self) -> Vec<Point3<f64>> {
        self.map.clone()
    }
}

keylo_plugin::export_plugin! {
    name: "follower",
    version: "1.0.0",
    registrar: Follower => "follows the motion prior",
}

fn build(info: *const KeyloPluginInfo) -> Box<dyn Registrar> {
    // SAFETY: a table of this binary (the exported one, or a static v2 table below).
    let plugin = unsafe { Plugin::from_info(info, Path::new("(this test)")) }
        .map(Arc::new)
        .unwrap();
    let mut registry = Registry::default();
    register_plugin(&mut registry, &plugin);
    let kind = format!("plugin:{}", plugin.name);
    registry
        .registrars
        .get(&kind)
        .unwrap()
        .build(&toml::Table::new(), &Default::default())
        .unwrap()
}

fn cloud(stamp: f64) -> PointCloud {
    PointCloud {
        timestamp: stamp,
        points: vec![Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 2.0, 0.0)],
        ..PointCloud::default()
    }
}

#[test]
fn hooks_reach_a_version_3_plugin_through_the_c_abi() {
    let mut r = build(keylo_plugin_entry());
    r.register(&cloud(0.0)).unwrap();
    r.set_motion_prior(&Pose::translation(0.5, 0.0, 0.0))
        .unwrap();
    let reg = r.register(&cloud(0.1)).unwrap();
    assert_eq!(reg.pose.translation.x, 0.5);
    // The map crosses the ABI as doubles, world frame.
    let map = r.local_map();
    assert_eq!(
        map,
        vec![Point3::new(1.5, 0.0, 0.0), Point3::new(0.5, 2.0, 0.0)]
    );
    r.set_pose(&Pose::translation(10.0, 0.0, 0.0)).unwrap();
    assert_eq!(r.register(&cloud(0.2)).unwrap().pose.translation.x, 10.0);
    r.reset().unwrap();
    assert!(r.local_map().is_empty());
    assert_eq!(r.register(&cloud(0.3)).unwrap().pose, Pose::identity());
    // A prior that is not rigid is refused before it reaches the plugin.
    let mut bad = Pose::identity();
    bad.rotation = nalgebra::Unit::new_unchecked(nalgebra::Quaternion::new(2.0, 0.0, 0.0, 0.0));
    let e = r.set_motion_prior(&bad).unwrap_err().to_string();
    assert!(e.contains("not a rigid transform"), "{e}");
}

/// A version-2 plugin's table around the exported follower's own functions: its kind in an
/// array of the shorter element, as a plugin built against `keylo_plugin_v2.h` lays it out.
fn v2_table() -> KeyloPluginInfo {
    // SAFETY: this binary's own exported table, valid for the life of the process.
    let v3 = unsafe { &*keylo_plugin_entry() };
    // SAFETY: one kind, as exported above.
    let k = unsafe { &*v3.kinds };
    let kinds: &'static [KindV2; 1] = Box::leak(Box::new([KindV2::from(k)]));
    KeyloPluginInfo {
        abi_version: 2,
        name: c"old-follower".as_ptr(),
        version: v3.version,
        kinds: kinds.as_ptr().cast(),
        kind_count: 1,
    }
}

#[test]
fn a_version_2_plugin_loads_and_its_hooks_say_it_does_not_offer_them() {
    let info: &'static KeyloPluginInfo = Box::leak(Box::new(v2_table()));
    let mut r = build(info);
    r.register(&cloud(0.0)).unwrap();
    let e = r
        .set_motion_prior(&Pose::translation(0.5, 0.0, 0.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("plugin `old-follower`"), "{e}");
    assert!(e.contains("does not offer `set_motion_prior`"), "{e}");
    assert!(e.contains("this plugin is ABI 2"), "{e}");
    assert!(r.reset().is_err() && r.set_pose(&Pose::identity()).is_err());
    assert!(r.local_map().is_empty());
    // Registration itself works as before.
    assert!(r.register(&cloud(0.1)).unwrap().converged);
}
