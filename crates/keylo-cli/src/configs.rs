//! Loading configs: file or built-in demo, then `--data` and `--set` overrides.

use std::path::Path;

use anyhow::{bail, Result};
use keylo::config::{PipelineConfig, RawConfig, Trust};
use keylo::Registry;

/// The built-in demo config (`configs/demo.toml`).
pub const DEMO: &str = include_str!("../../../configs/demo.toml");

/// Reads `file` (or the demo when `None` and no `--data`), applies `--data` and `--set`, loads
/// the plugins it names (`kind = "plugin:NAME"`) into the registry and resolves it.
pub fn load(
    registry: &mut Registry,
    file: Option<&Path>,
    data: Option<&Path>,
    meta: Option<&Path>,
    sets: &[String],
    trust: Trust,
) -> Result<PipelineConfig> {
    let mut raw = match (file, data) {
        (Some(path), _) => RawConfig::from_file(path)?,
        (None, None) => RawConfig::parse("built-in demo (configs/demo.toml)", DEMO)?,
        (None, Some(_)) => RawConfig::builtin(),
    };
    if let Some(data) = data {
        if let Some(s) = sets
            .iter()
            .find(|s| s.trim_start().starts_with("source.kind"))
        {
            bail!("--set {s} conflicts with --data: --data chooses the source kind from the data");
        }
        apply_data(registry, &mut raw, data)?;
    }
    if let Some(meta) = meta {
        apply_meta(&mut raw, meta)?;
    }
    finish(registry, raw, sets, trust)
}

/// Reads `file` (or, when `None`, the built-in defaults, not the demo), applies `--set`,
/// loads the plugins it names and resolves it (`keylo ros2`, whose input is a topic).
#[cfg_attr(not(feature = "ros2"), allow(dead_code))]
pub fn load_or_defaults(
    registry: &mut Registry,
    file: Option<&Path>,
    sets: &[String],
    trust: Trust,
) -> Result<PipelineConfig> {
    let raw = match file {
        Some(path) => RawConfig::from_file(path)?,
        None => RawConfig::builtin(),
    };
    finish(registry, raw, sets, trust)
}

fn finish(
    registry: &mut Registry,
    mut raw: RawConfig,
    sets: &[String],
    trust: Trust,
) -> Result<PipelineConfig> {
    for s in sets {
        raw.set(s)?;
    }
    keylo::plugin::load_for_config(registry, &raw, trust)?;
    let mut config = registry.resolve(&raw)?;
    config.trust = trust;
    Ok(config)
}

fn apply_data(registry: &Registry, raw: &mut RawConfig, data: &Path) -> Result<()> {
    let (kind, path) = registry
        .source_for_data(data)
        .map_err(|e| anyhow::anyhow!("--data {e}"))?;
    let kind = kind.as_str();
    // Same kind as the config's source: keep its other parameters (start, max_frames, …).
    let mut table = match raw.table.get("source").and_then(toml::Value::as_table) {
        Some(t) if t.get("kind").and_then(toml::Value::as_str) == Some(kind) => t.clone(),
        _ => toml::Table::new(),
    };
    table.insert("kind".into(), toml::Value::String(kind.into()));
    table.insert(
        "path".into(),
        toml::Value::String(path.display().to_string()),
    );
    raw.replace_section("source", table);
    Ok(())
}

/// `--meta FILE`: the sensor metadata of the source (`[source] meta`, Ouster captures).
fn apply_meta(raw: &mut RawConfig, meta: &Path) -> Result<()> {
    if !meta.is_file() {
        bail!("--meta {}: no such file", meta.display());
    }
    let path = std::path::absolute(meta).unwrap_or_else(|_| meta.to_path_buf());
    let Some(source) = raw
        .table
        .get_mut("source")
        .and_then(toml::Value::as_table_mut)
    else {
        bail!("--meta needs a source: give --data or a config with a [source] section");
    };
    source.insert(
        "meta".into(),
        toml::Value::String(path.display().to_string()),
    );
    Ok(())
}

/// The source of `keylo info` / `keylo convert`: the data path's detected kind, its metadata
/// and overrides; also returns the source kind.
pub fn open_data(
    registry: &mut Registry,
    data: &crate::arg_groups::DataArgs,
) -> Result<(String, Box<dyn keylo::ImageSource>)> {
    let config = load(
        registry,
        None,
        Some(&data.data),
        data.meta.as_deref(),
        &data.sets,
        // No config file: whatever libraries it names come from the user's own `--set`.
        Trust::Config,
    )?;
    let source = keylo::build_source(&config, registry)?;
    Ok((config.source.kind, source))
}
