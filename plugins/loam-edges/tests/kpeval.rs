//! The built plugin evaluated like any built-in detector by keylo's keypoint evaluation
//! (`keylo keypoints eval --plugin-dir DIR --combos plugin:loam-edges_BRIEF`).

use keylo::kpeval::{evaluate, parse_combos, ComboSet, EvalOptions, EvalSpec, Plane};
use keylo::plugin::host::register_plugin;
use keylo::plugin::{Plugin, SearchPath};
use keylo::sim::{SimConfig, SimSource};
use keylo::{BuildContext, Channel, ImageSource};

#[test]
fn the_plugin_is_evaluated_with_every_metric() {
    let dir = std::env::current_exe()
        .expect("test binary path")
        .parent()
        .expect("deps folder")
        .to_path_buf();
    let mut registry = keylo::registry();
    let lib = SearchPath::new(&[dir]).find("loam-edges").unwrap();
    register_plugin(&mut registry, &Plugin::open(&lib).unwrap());
    let combos = parse_combos(
        &ComboSet::parse("plugin:loam-edges_BRIEF,plugin:loam-edges_SIFT"),
        &registry,
    )
    .unwrap();
    assert_eq!(combos[0].detector, "plugin:loam-edges");
    let mut spec = EvalSpec::default();
    spec.image.channel = "range".into();
    let config = SimConfig {
        frames: 3,
        ..SimConfig::default()
    };
    let mut source = SimSource::new(&config).unwrap();
    let mut planes = Vec::new();
    while let Some(frame) = source.next_frame() {
        let frame = frame.unwrap();
        planes.push(Plane::from_frame(
            &frame,
            Channel::Range,
            &spec.image.normalise_for(Channel::Range, &frame.beams.model),
            String::new(),
        ));
    }
    let opts = EvalOptions {
        jobs: 1,
        skip_unavailable: false,
        progress: None,
    };
    let res = evaluate(
        &planes,
        &combos,
        &spec,
        &registry,
        &BuildContext::default(),
        &opts,
    )
    .unwrap();
    assert!(res.failed.is_empty(), "{:?}", res.failed);
    assert_eq!(res.rows.len(), 6);
    for r in &res.rows {
        assert!(r.keypoints > 10, "{r:?}");
        assert!(r.robustness_rotation.is_some_and(|v| v > 0.3), "{r:?}");
    }
    for r in res.rows.iter().filter(|r| r.index > 0) {
        assert!(r.match_ratio.is_some_and(|v| v > 0.3), "{r:?}");
    }
}
