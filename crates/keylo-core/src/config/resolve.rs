use super::{OutputConfig, PipelineConfig, RawConfig, StageConfig, SECTIONS, STAGE_DEFAULT_KINDS};
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
        })
    }

    fn resolve_stage(&self, raw: &RawConfig, section: &str) -> Result<StageConfig, ConfigError> {
        let invalid = |path: String, message: String| ConfigError::Invalid {
            origin: raw.origin.clone(),
            path,
            message,
        };
        let mut params = match raw.table.get(section) {
            None => toml::Table::new(),
            Some(toml::Value::Table(t)) => t.clone(),
            Some(other) => {
                return Err(invalid(
                    section.into(),
                    format!(
                        "expected a table `[{section}]`, found a value of type {}",
                        other.type_str()
                    ),
                ))
            }
        };
        let default_kind = STAGE_DEFAULT_KINDS
            .iter()
            .find(|(s, _)| *s == section)
            .map_or("none", |(_, k)| *k);
        let kind = match params.remove("kind") {
            None => default_kind.to_string(),
            Some(toml::Value::String(s)) => s,
            Some(other) => {
                return Err(invalid(
                    format!("{section}.kind"),
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
                    format!("{section}.{key}"),
                    format!("`{section}.kind = \"none\"` takes no parameters"),
                ));
            }
            return Ok(StageConfig { kind, params });
        }
        let resolved = self
            .resolve_params(section, &kind, &params)
            .ok_or_else(|| {
                let mut allowed = self.section_kinds(section).unwrap_or_default();
                if optional {
                    allowed.insert(0, "none");
                }
                ConfigError::UnknownKind {
                    origin: raw.origin.clone(),
                    section: section.into(),
                    kind: kind.clone(),
                    allowed: allowed.join(", "),
                }
            })?;
        let params = resolved.map_err(|(path, message)| {
            let path = if path.is_empty() {
                section.to_string()
            } else {
                format!("{section}.{path}")
            };
            invalid(path, format!("{message} (backend `{kind}`)"))
        })?;
        Ok(StageConfig { kind, params })
    }
}

fn resolve_output(raw: &RawConfig) -> Result<OutputConfig, ConfigError> {
    let table = match raw.table.get("output") {
        None => return Ok(OutputConfig::default()),
        Some(toml::Value::Table(t)) => t.clone(),
        Some(other) => {
            return Err(ConfigError::Invalid {
                origin: raw.origin.clone(),
                path: "output".into(),
                message: format!(
                    "expected a table `[output]`, found a value of type {}",
                    other.type_str()
                ),
            })
        }
    };
    parse_params::<OutputConfig>(&table).map_err(|(path, message)| ConfigError::Invalid {
        origin: raw.origin.clone(),
        path: format!("output.{path}"),
        message,
    })
}
