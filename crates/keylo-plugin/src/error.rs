//! Errors of the plugin loader. Every variant names the library file.

use std::path::PathBuf;

/// A plugin that cannot be found, loaded or used.
#[derive(Debug, thiserror::Error)]
pub enum PluginError {
    /// No library of that name in any searched folder.
    #[error("plugin `{name}` not found: looked for {files} in {searched}")]
    NotFound {
        name: String,
        /// The file names tried, joined by ", ".
        files: String,
        /// The folders searched, each with where it came from, joined by "; ".
        searched: String,
    },
    /// The dynamic loader refused the file.
    #[error("{path}: cannot load plugin library: {message}")]
    Open { path: PathBuf, message: String },
    /// The library does not export the entry symbol.
    #[error("{path}: no symbol `{symbol}`: not a keylo plugin (a Rust plugin needs `keylo_plugin::export_plugin!`, a C plugin must define `{symbol}`)")]
    MissingEntry { path: PathBuf, symbol: String },
    /// The plugin was built against another ABI version.
    #[error("{path}: plugin ABI version {found} is not supported: this keylo supports ABI versions {supported}; rebuild the plugin against this keylo's keylo_plugin.h")]
    AbiMismatch {
        path: PathBuf,
        found: u32,
        /// The accepted versions, joined by ", ".
        supported: String,
    },
    /// The descriptor table is malformed.
    #[error("{path}: invalid plugin descriptor: {message}")]
    Invalid { path: PathBuf, message: String },
    /// The plugin offers no backend for the stage that names it.
    #[error("`[{section}] kind = \"plugin:{name}\"`: plugin `{name}` ({path}) offers no {section}; it offers: {offered}")]
    WrongStage {
        name: String,
        path: PathBuf,
        section: String,
        offered: String,
    },
    /// The file's plugin has another name than the one looked for.
    #[error("{path}: the library's plugin is named `{found}`, not `{expected}`")]
    NameMismatch {
        path: PathBuf,
        expected: String,
        found: String,
    },
    /// A plugin name that is not a plain name (a path, `..`): it could name a file outside
    /// every plugin folder.
    #[error("`[{section}] kind = \"plugin:{name}\"`: a plugin name is letters, digits, `-` and `_` only (no path); install the library in a plugin folder and name it by its plugin name")]
    BadName { section: String, name: String },
    /// The `[plugins]` section is invalid.
    #[error(transparent)]
    Config(#[from] keylo_core::ConfigError),
}
