//! The Rust API checks trust too: a stage naming its own ONNX Runtime library is refused when
//! built from a config resolved under the default `Trust::Installed`, before the path is
//! even looked at; under `Trust::Config` the path is used (here: a missing file, named).

use keylo::config::{RawConfig, Trust};
use keylo::Odometry;

#[test]
fn a_stage_naming_its_own_runtime_needs_trust_even_through_odometry_build() {
    let registry = keylo::registry();
    let raw = RawConfig::parse(
        "t.toml",
        "[detector]\nkind = \"superpoint\"\nonnxruntime = \"/nonexistent/libonnxruntime.so\"\n",
    )
    .unwrap();
    let mut config = registry.resolve(&raw).unwrap();
    let refused = Odometry::build(&config, &registry)
        .err()
        .unwrap()
        .to_string();
    assert!(
        refused.contains("/nonexistent/libonnxruntime.so (onnxruntime)")
            && refused.contains("--trust-plugins"),
        "{refused}"
    );
    config.trust = Trust::Config;
    let used = Odometry::build(&config, &registry)
        .err()
        .unwrap()
        .to_string();
    assert!(used.contains("no such file"), "{used}");
}
