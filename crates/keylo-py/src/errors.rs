//! keylo's errors as a small hierarchy of Python exceptions.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    keylo,
    KeyloError,
    PyException,
    "Base class of every keylo error."
);
create_exception!(
    keylo,
    ConfigError,
    KeyloError,
    "A config (TOML, dict or typed) that keylo rejects; the message names the key."
);
create_exception!(
    keylo,
    DataError,
    KeyloError,
    "Input data that cannot be read or used: a file, a frame, a point array."
);
create_exception!(
    keylo,
    StageError,
    KeyloError,
    "A pipeline stage failed on a frame (e.g. the registrar diverged)."
);
create_exception!(
    keylo,
    PluginError,
    KeyloError,
    "A run-time plugin or a Python detector failed."
);

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("KeyloError", py.get_type::<KeyloError>())?;
    m.add("ConfigError", py.get_type::<ConfigError>())?;
    m.add("DataError", py.get_type::<DataError>())?;
    m.add("StageError", py.get_type::<StageError>())?;
    m.add("PluginError", py.get_type::<PluginError>())?;
    Ok(())
}

/// A core error as the Python exception of its kind.
pub fn core(e: keylo::CoreError) -> PyErr {
    use keylo::CoreError as E;
    let text = e.to_string();
    match e {
        E::Config(_) => ConfigError::new_err(text),
        E::BadFrame { .. } | E::Input { .. } | E::Io { .. } => DataError::new_err(text),
        E::Stage { .. } => StageError::new_err(text),
    }
}

/// A frontend error as the Python exception of its kind.
pub fn frontend(e: keylo::Error) -> PyErr {
    use keylo::Error as E;
    match e {
        E::Config(c) => ConfigError::new_err(c.to_string()),
        E::Core(c) => core(c),
        E::Plugin(p) => PluginError::new_err(p.to_string()),
        E::Map(m @ keylo::map::MapError::Config { .. }) => ConfigError::new_err(m.to_string()),
        other => DataError::new_err(other.to_string()),
    }
}

/// A config error.
pub fn config(e: keylo::ConfigError) -> PyErr {
    ConfigError::new_err(e.to_string())
}
