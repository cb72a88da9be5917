use std::collections::BTreeMap;

use super::Trust;
use super::{
    default_kind, OutputConfig, PipelineConfig, RawConfig, StageConfig, BY_IMAGE_KEY,
    PER_IMAGE_STAGES, SECTIONS,
};
use crate::registry::parse_params;
use crate::{ConfigError, Registry};

/// Stages that may be absent (`kind = "none"`).
const OPTIONAL_STAGES: [&str; 3] = ["image", "detector", "descriptor"];

impl Registry {
    /// Validates a raw config against the registered backends and fills every default.
    ///
    /// Unknown sections, unknown kinds, unknown keys and wrong types are errors that name the
    /// key path and what is allowed.
    pub fn resolve(&self, raw: &RawConfig) -> Result<PipelineConfig, ConfigError> {
        for key in raw.table.keys() {
            if !SECTIONS.contains(&key.as_str()) {
                return Err(ConfigError::UnknownSection {
                    origin: raw.origin.clone(),
                    section: key.clone(),
                    allowed: SECTIONS.join(", "),
                });
            }
        }
        let stage = |name: &str| self.resolve_stage(raw, name);
        Ok(PipelineConfig {
            origin: raw.origin.clone(),
            base_dir: raw.base_dir.clone(),
            source: stage("source")?,
            image: stage("image")?,
            detector: stage("detector")?,
            descriptor: stage("descriptor")?,
            downsampler: stage("downsampler")?,
            registrar: stage("registrar")?,
            output: resolve_output(raw)?,
            plugins: raw.plugins()?,
            ros2: match raw.table.get("ros2") {
                None => toml::Table::new(),
                Some(value) => expect_table(&raw.origin, "ros2", value)?,
            },
            map: match raw.table.get("map") {
                None => toml::Table::new(),
                Some(value) => expect_table(&raw.origin, "map", value)?,
            },
            localise: match raw.table.get("localise") {
                None => toml::Table::new(),
                Some(value) => expect_table(&raw.origin, "localise", value)?,
            },
            trust: Trust::Installed,
        })
    }

    fn resolve_stage(&self, raw: &RawConfig, section: &str) -> Result<StageConfig, ConfigError> {
        let params = match raw.table.get(section) {
            None => toml::Table::new(),
            Some(value) => expect_table(&raw.origin, section, value)?,
        };
        self.resolve_stage_table(&raw.origin, section, section, params)
    }

    /// Resolves one stage table found at `path` (`detector`, `detector.by_image.range`).
    fn resolve_stage_table(
        &self,
        origin: &str,
        section: &str,
        path: &str,
        mut params: toml::Table,
    ) -> Result<StageConfig, ConfigError> {
        let invalid = |path: String, message: String| ConfigError::Invalid {
            origin: origin.into(),
            path,
            message,
        };
        let by_image = match params.remove(BY_IMAGE_KEY) {
            Some(value) if PER_IMAGE_STAGES.contains(&section) && path == section => {
                self.resolve_by_image(origin, section, &value)?
            }
            Some(_) => {
                return Err(invalid(
                    format!("{path}.{BY_IMAGE_KEY}"),
                    format!(
                        "per-image overrides are allowed only directly in [{}]",
                        PER_IMAGE_STAGES.join("], [")
                    ),
                ))
            }
            None => Default::default(),
        };
        let kind = match params.remove("kind") {
            None => default_kind(section).to_string(),
            Some(toml::Value::String(s)) => s,
            Some(other) => {
                return Err(invalid(
                    format!("{path}.kind"),
                    format!(
                        "expected a string, found a value of type {}",
                        other.type_str()
                    ),
                ))
            }
        };
        let optional = OPTIONAL_STAGES.contains(&section);
        if kind == "none" && optional {
            if let Some(key) = params.keys().next() {
                return Err(invalid(
                    format!("{path}.{key}"),
                    format!("`{path}.kind = \"none\"` takes no parameters"),
                ));
            }
            return Ok(StageConfig {
                kind,
                params,
                by_image,
            });
        }
        let resolved = self
            .resolve_params(section, &kind, &params)
            .ok_or_else(|| {
                let mut allowed = self.section_kinds(section).unwrap_or_default();
                if optional {
                    allowed.insert(0, "none");
                }
                ConfigError::UnknownKind {
                    origin: origin.into(),
                    section: path.into(),
                    kind: kind.clone(),
                    allowed: allowed.join(", "),
                }
            })?;
        let params = resolved.map_err(|(key, message)| {
            let key = if key.is_empty() {
                path.to_string()
            } else {
                format!("{path}.{key}")
            };
            invalid(key, format!("{message} (backend `{kind}`)"))
        })?;
        Ok(StageConfig {
            kind,
            params,
            by_image,
        })
    }

    fn resolve_by_image(
        &self,
        origin: &str,
        section: &str,
        value: &toml::Value,
    ) -> Result<BTreeMap<String, StageConfig>, ConfigError> {
        let path = format!("{section}.{BY_IMAGE_KEY}");
        let table = expect_table(origin, &path, value)?;
        let mut out = BTreeMap::new();
        for (image, entry) in table {
            let entry_path = format!("{path}.{image}");
            let params = expect_table(origin, &entry_path, &entry)?;
            let stage = self.resolve_stage_table(origin, section, &entry_path, params)?;
            out.insert(image, stage);
        }
        Ok(out)
    }
}

fn expect_table(origin: &str, path: &str, value: &toml::Value) -> Result<toml::Table, ConfigError> {
    match value {
        toml::Value::Table(t) => Ok(t.clone()),
        other => Err(ConfigError::Invalid {
            origin: origin.into(),
            path: path.into(),
            message: format!(
                "expected a table `[{path}]`, found a value of type {}",
                other.type_str()
            ),
        }),
    }
}

impl RawConfig {
    /// The `[plugins]` section, validated (the plugin loader reads it before resolving, since
    /// plugin kinds must be registered first).
    pub fn plugins(&self) -> Result<super::PluginsConfig, ConfigError> {
        let table = match self.table.get("plugins") {
            None => return Ok(super::PluginsConfig::default()),
            Some(value) => expect_table(&self.origin, "plugins", value)?,
        };
        parse_params::<super::PluginsConfig>(&table).map_err(|(path, message)| {
            ConfigError::Invalid {
                origin: self.origin.clone(),
                path: format!("plugins.{path}"),
                message,
            }
        })
    }
}

fn resolve_output(raw: &RawConfig) -> Result<OutputConfig, ConfigError> {
    let table = match raw.table.get("output") {
        None => return Ok(OutputConfig::default()),
        Some(value) => expect_table(&raw.origin, "output", value)?,
    };
    let output =
        parse_params::<OutputConfig>(&table).map_err(|(path, message)| ConfigError::Invalid {
            origin: raw.origin.clone(),
            path: format!("output.{path}"),
            message,
        })?;
    let sigma = output.covariance_sigma_m;
    if !(sigma.is_finite() && sigma >= 0.0) {
        return Err(ConfigError::Invalid {
            origin: raw.origin.clone(),
            path: "output.covariance_sigma_m".into(),
            message: format!(
                "{sigma}: expected 0 (the registrar's fitted value) or a positive number of metres"
            ),
        });
    }
    Ok(output)
}
