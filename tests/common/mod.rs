//! Helpers shared by the cross-crate tests.

use keylo::config::{PipelineConfig, RawConfig};

/// The config `text` resolved, with the registry (every built-in backend) it was resolved by.
pub fn resolve(text: &str) -> (keylo::Registry, PipelineConfig) {
    let registry = keylo::registry();
    let config = registry
        .resolve(&RawConfig::parse("test", text).unwrap())
        .unwrap();
    (registry, config)
}
