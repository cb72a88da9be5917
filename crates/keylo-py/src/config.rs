//! A config given from Python: a TOML file path, TOML text, or a dict of the same keys.

use std::path::PathBuf;

use keylo::config::RawConfig;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::errors::{config, ConfigError};

/// `config` as a raw config: a `str` naming an existing `.toml` file or a `pathlib.Path` is
/// read (relative paths in it resolve against its folder), other text is parsed as TOML, a
/// dict is taken key by key; `None` is the built-in default config.
pub fn raw_config(config_arg: Option<&Bound<'_, PyAny>>) -> PyResult<RawConfig> {
    let Some(arg) = config_arg else {
        return Ok(RawConfig::builtin());
    };
    if arg.is_none() {
        return Ok(RawConfig::builtin());
    }
    if let Ok(dict) = arg.cast::<PyDict>() {
        let table = table_of(dict, "")?;
        return Ok(RawConfig {
            origin: "config dict".into(),
            base_dir: PathBuf::from("."),
            table,
        });
    }
    if let Ok(text) = arg.cast::<PyString>() {
        let text = text.to_str()?;
        let path = PathBuf::from(text);
        let looks_like_file = !text.contains('\n') && text.ends_with(".toml");
        if looks_like_file {
            return RawConfig::from_file(&path).map_err(config);
        }
        return RawConfig::parse("config text", text).map_err(config);
    }
    // A path-like object (pathlib.Path): its file-system path.
    if let Ok(path) = arg.extract::<PathBuf>() {
        return RawConfig::from_file(&path).map_err(config);
    }
    Err(ConfigError::new_err(format!(
        "config: expected a TOML file path, TOML text or a dict, got {}",
        arg.get_type().name()?
    )))
}

/// A Python dict as a TOML table (keys must be strings); `at` is the key path for messages.
pub fn table_of(dict: &Bound<'_, PyDict>, at: &str) -> PyResult<toml::Table> {
    let mut table = toml::Table::new();
    for (k, v) in dict.iter() {
        let key: String = k.extract().map_err(|_| {
            ConfigError::new_err(format!("config{at}: every key must be a string, got {k}"))
        })?;
        let path = format!("{at}.{key}");
        if v.is_none() {
            continue;
        }
        table.insert(key, value_of(&v, &path)?);
    }
    Ok(table)
}

fn value_of(v: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract().map_err(|_| {
            ConfigError::new_err(format!("config{path}: {v} does not fit 64 bits"))
        })?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_str()?.to_string()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        return Ok(toml::Value::Table(table_of(d, path)?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: PyResult<Vec<toml::Value>> = v
            .try_iter()?
            .enumerate()
            .map(|(i, item)| value_of(&item?, &format!("{path}[{i}]")))
            .collect();
        return Ok(toml::Value::Array(items?));
    }
    if let Ok(p) = v.extract::<PathBuf>() {
        return Ok(toml::Value::String(p.display().to_string()));
    }
    Err(ConfigError::new_err(format!(
        "config{path}: a {} is not a config value (bool, int, float, str, list or dict)",
        v.get_type().name()?
    )))
}
