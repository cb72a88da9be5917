//! The simulator's parameters from the command line (`keylo sim`, `keylo sim realism`).

use anyhow::Result;
use keylo::config::RawConfig;
use keylo::core::registry::parse_params;
use keylo::sim::SimConfig;

/// The simulator's parameters: `scene`, `frames` and `KEY=VALUE` settings on the defaults.
pub fn sim_config(scene: &str, frames: usize, sets: &[String]) -> Result<SimConfig> {
    let mut raw = RawConfig::builtin();
    raw.set(&format!("scene={scene}"))?;
    raw.set(&format!("frames={frames}"))?;
    for s in sets {
        raw.set(s)?;
    }
    parse_params::<SimConfig>(&raw.table)
        .map_err(|(path, msg)| anyhow::anyhow!("simulator parameter `{path}`: {msg}"))
}
