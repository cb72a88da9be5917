use std::path::{Path, PathBuf};

use super::BY_IMAGE_KEY;
use crate::ConfigError;

/// A config as written: the parsed TOML table plus where it came from.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RawConfig {
    /// File path or `built-in`, used in messages.
    pub origin: String,
    /// Directory relative paths are resolved against.
    pub base_dir: PathBuf,
    pub table: toml::Table,
}

/// One table of a stage section in a raw config: the section itself or one of its
/// `by_image` overrides ([`RawConfig::stage_tables`]).
#[derive(Debug, Clone)]
pub struct StageTable<'a> {
    /// `detector`, `descriptor`, `downsampler` or `registrar`.
    pub section: &'static str,
    /// The table's key path (`detector`, `detector.by_image.range`).
    pub path: String,
    pub table: &'a toml::Table,
}

impl RawConfig {
    /// The tables of the per-frame stage sections (`detector`, `descriptor`, `downsampler`,
    /// `registrar`), each followed by its `by_image` overrides; a section or override that
    /// is not a table is left out (resolving the config reports it).
    pub fn stage_tables(&self) -> Vec<StageTable<'_>> {
        let mut out = Vec::new();
        for section in ["detector", "descriptor", "downsampler", "registrar"] {
            let Some(table) = self.table.get(section).and_then(toml::Value::as_table) else {
                continue;
            };
            out.push(StageTable {
                section,
                path: section.to_string(),
                table,
            });
            if let Some(by) = table.get(BY_IMAGE_KEY).and_then(toml::Value::as_table) {
                out.extend(by.iter().filter_map(|(image, t)| {
                    Some(StageTable {
                        section,
                        path: format!("{section}.{BY_IMAGE_KEY}.{image}"),
                        table: t.as_table()?,
                    })
                }));
            }
        }
        out
    }

    /// The empty config: every section takes its defaults.
    pub fn builtin() -> Self {
        Self {
            origin: "built-in".into(),
            base_dir: PathBuf::from("."),
            table: toml::Table::new(),
        }
    }

    /// Reads and parses a TOML file.
    pub fn from_file(path: &Path) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let mut raw = Self::parse(&path.display().to_string(), &text)?;
        raw.base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(raw)
    }

    /// Parses TOML text; `origin` names it in messages.
    pub fn parse(origin: &str, text: &str) -> Result<Self, ConfigError> {
        let table = text
            .parse::<toml::Table>()
            .map_err(|e| ConfigError::Syntax {
                origin: origin.into(),
                message: e.to_string(),
            })?;
        Ok(Self {
            origin: origin.into(),
            base_dir: PathBuf::from("."),
            table,
        })
    }

    /// Applies `key.path=value`; the value is read as TOML (`0.5`, `true`, `"x"`, `[1, 2]`)
    /// and taken as a plain string when it is not valid TOML.
    pub fn set(&mut self, text: &str) -> Result<(), ConfigError> {
        let err = |message: &str| ConfigError::Override {
            text: text.into(),
            message: message.into(),
        };
        let (key, value) = text
            .split_once('=')
            .ok_or_else(|| err("expected key.path=value"))?;
        let keys: Vec<&str> = key.trim().split('.').collect();
        if keys.iter().any(|k| k.is_empty()) {
            return Err(err("empty key in path"));
        }
        let value = parse_value(value.trim());
        let (last, parents) = keys.split_last().ok_or_else(|| err("empty key"))?;
        let mut table = &mut self.table;
        for k in parents {
            let entry = table
                .entry((*k).to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            table = entry
                .as_table_mut()
                .ok_or_else(|| err(&format!("`{k}` is a value, not a table")))?;
        }
        if *last == "kind" && table.get("kind") != Some(&value) {
            // A new backend: the old backend's parameters would not fit it.
            table.clear();
        }
        table.insert((*last).to_string(), value);
        Ok(())
    }

    /// Replaces a whole section (used by `--data`, which picks a source kind and path).
    pub fn replace_section(&mut self, section: &str, table: toml::Table) {
        self.table.insert(section.into(), toml::Value::Table(table));
    }
}

fn parse_value(text: &str) -> toml::Value {
    format!("v = {text}")
        .parse::<toml::Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(text.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_parses_typed_values_and_creates_tables() {
        let mut raw = RawConfig::builtin();
        raw.set("registrar.voxel_size=0.5").unwrap();
        raw.set("source.scene=corridor").unwrap();
        raw.set("output.tum=false").unwrap();
        let reg = raw.table["registrar"].as_table().cloned().unwrap();
        assert_eq!(reg["voxel_size"].as_float(), Some(0.5));
        assert_eq!(raw.table["source"]["scene"].as_str(), Some("corridor"));
        assert_eq!(raw.table["output"]["tum"].as_bool(), Some(false));
    }

    #[test]
    fn set_kind_drops_old_parameters() {
        let mut raw =
            RawConfig::parse("t", "[registrar]\nkind='kiss-icp'\nvoxel_size=1.0").unwrap();
        raw.set("registrar.kind=ndt").unwrap();
        let reg = raw.table["registrar"].as_table().cloned().unwrap();
        assert_eq!(reg.len(), 1);
    }

    #[test]
    fn bad_overrides_are_errors() {
        let mut raw = RawConfig::builtin();
        assert!(raw.set("novalue").is_err());
        assert!(raw.set("a..b=1").is_err());
        raw.set("a=1").unwrap();
        let e = raw.set("a.b=1").err().map(|e| e.to_string()).unwrap();
        assert!(e.contains("`a` is a value"), "{e}");
    }

    #[test]
    fn syntax_errors_name_the_origin() {
        let e = RawConfig::parse("my.toml", "[source\n")
            .err()
            .map(|e| e.to_string())
            .unwrap();
        assert!(e.starts_with("my.toml: invalid TOML"), "{e}");
    }
}
