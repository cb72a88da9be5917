//! The built plugin library, loaded through keylo's loader from
//! `configs/examples/lab-loam-edges-kiss-icp.toml`, runs five simulated frames.

use std::path::{Path, PathBuf};

use keylo::config::{RawConfig, Trust};
use keylo::Pipeline;

/// Where cargo put `libloam_edges.so` (beside this test binary).
fn plugin_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.parent().expect("deps folder").to_path_buf()
}

#[test]
fn example_config_runs_with_the_built_plugin() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let file = root.join("configs/examples/lab-loam-edges-kiss-icp.toml");
    let mut raw = RawConfig::from_file(&file).unwrap();
    for s in [
        "source.frames=5",
        "source.sensor=os1-64",
        "source.columns=512",
    ] {
        raw.set(s).unwrap();
    }
    raw.set(&format!("plugins.dirs=[\"{}\"]", plugin_dir().display()))
        .unwrap();
    let mut registry = keylo::registry();
    // The library is in a folder the config names: refused until the config is trusted.
    let refused = keylo::plugin::load_for_config(&mut registry, &raw, Trust::Installed)
        .unwrap_err()
        .to_string();
    assert!(refused.contains("--trust-plugins"), "{refused}");
    let loaded = keylo::plugin::load_for_config(&mut registry, &raw, Trust::Config).unwrap();
    assert_eq!(loaded.len(), 1);
    assert_eq!(loaded[0].name, "loam-edges");
    assert_eq!(loaded[0].version, env!("CARGO_PKG_VERSION"));
    let config = registry.resolve(&raw).unwrap();
    let mut pipeline = Pipeline::build(&config, &registry).unwrap();
    let gt = pipeline
        .source
        .ground_truth()
        .expect("the simulator has ground truth");
    let mut last = None;
    while let Some(r) = pipeline.step() {
        let r = r.unwrap();
        assert!(
            r.keypoints > 50,
            "frame {}: {} keypoints",
            r.index,
            r.keypoints
        );
        assert!(r.cloud_points < 512 * 64, "{}", r.cloud_points);
        last = Some(r);
    }
    let last = last.expect("five frames");
    assert_eq!(last.index, 4);
    let est = last.pose.translation.vector;
    assert!(est.iter().all(|v| v.is_finite()));
    let (g0, g4) = (gt.poses[0], gt.poses[4]);
    let truth = (g0.inverse() * g4).translation.vector;
    assert!(truth.norm() > 0.01, "the simulated sensor moves: {truth:?}");
    assert!(
        (est - truth).norm() < 0.1,
        "estimated {est:?}, true {truth:?}"
    );
}
