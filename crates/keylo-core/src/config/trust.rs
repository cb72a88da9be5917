//! Whether the code a config names may run.
//!
//! A config is data people share (papers, issue threads). Loading a shared library runs its
//! initialisers, so the libraries a config names itself — plugins found in its
//! `[plugins] dirs`, a stage's `onnxruntime` path — load only when the caller trusts the
//! config ([`Trust::Config`]: `--trust-plugins`, `trust_plugins=True`, `KEYLO_TRUST_PLUGINS`).
//! Plugins the user installed (`KEYLO_PLUGIN_PATH`, `~/.local/lib/keylo/plugins`) and the
//! ONNX Runtime found in the usual places load either way. See docs/plugins.md.

use std::path::PathBuf;

use super::RawConfig;
use crate::ConfigError;

/// Which libraries a config may have loaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Trust {
    /// Only libraries installed where the user keeps them; a config naming its own is refused.
    #[default]
    Installed,
    /// Also the libraries the config names (its `[plugins] dirs`, `onnxruntime` paths).
    Config,
}

impl Trust {
    /// The trust of an interface's opt-in (`--trust-plugins`, `trust_plugins=True`,
    /// `KEYLO_TRUST_PLUGINS`): given, [`Trust::Config`]; not, [`Trust::Installed`].
    pub fn opted_in(opt_in: bool) -> Self {
        if opt_in {
            Self::Config
        } else {
            Self::Installed
        }
    }
}

/// How each interface opts in, for messages.
pub const OPT_IN: &str = "`--trust-plugins` on the command line, `trust_plugins=True` in \
Python, the flag KEYLO_TRUST_PLUGINS in C, `Trust::Config` in Rust";

/// One library a config names: the key naming it and the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NamedLibrary {
    /// `[plugins] dirs` or the stage key (`detector.onnxruntime`).
    pub key: String,
    pub path: PathBuf,
}

/// Every non-empty `onnxruntime` path in the config's stage sections (per-image tables too).
pub fn named_runtimes(raw: &RawConfig) -> Vec<NamedLibrary> {
    raw.stage_tables()
        .into_iter()
        .filter_map(|t| {
            let path = t
                .table
                .get("onnxruntime")
                .and_then(toml::Value::as_str)
                .filter(|p| !p.is_empty())?;
            Some(NamedLibrary {
                key: format!("{}.onnxruntime", t.path),
                path: PathBuf::from(path),
            })
        })
        .collect()
}

/// Refuses, under [`Trust::Installed`], a config that names libraries: `plugins` (the plugin
/// libraries found in its own folders) and its `onnxruntime` paths. Nothing is loaded here.
pub fn check(raw: &RawConfig, trust: Trust, plugins: &[NamedLibrary]) -> Result<(), ConfigError> {
    if trust == Trust::Config {
        return Ok(());
    }
    let mut named: Vec<NamedLibrary> = plugins.to_vec();
    named.extend(named_runtimes(raw));
    refuse(&raw.origin, trust, &named)
}

/// The one refusal of every trust check: under [`Trust::Installed`], `named` libraries (of
/// `origin`, for the message) are an error listing each with its key; none, or trusted, pass.
pub fn refuse(origin: &str, trust: Trust, named: &[NamedLibrary]) -> Result<(), ConfigError> {
    if trust == Trust::Config || named.is_empty() {
        return Ok(());
    }
    let libraries = named
        .iter()
        .map(|n| format!("{} ({})", n.path.display(), n.key))
        .collect::<Vec<_>>()
        .join(", ");
    Err(ConfigError::Untrusted {
        origin: origin.into(),
        libraries,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(text: &str) -> RawConfig {
        RawConfig::parse("t.toml", text).unwrap()
    }

    #[test]
    fn a_config_without_libraries_passes_untrusted() {
        let r = raw("[detector]\nkind = \"akaze\"\n");
        assert!(check(&r, Trust::Installed, &[]).is_ok());
    }

    #[test]
    fn onnxruntime_paths_are_refused_unless_trusted_and_named() {
        let r = raw(
            "[detector]\nkind = \"superpoint\"\nonnxruntime = \"lib/x.so\"\n\
             [detector.by_image.range]\nkind = \"superpoint\"\nonnxruntime = \"/y.so\"\n",
        );
        let e = check(&r, Trust::Installed, &[]).unwrap_err().to_string();
        assert!(e.contains("lib/x.so (detector.onnxruntime)"), "{e}");
        assert!(
            e.contains("/y.so (detector.by_image.range.onnxruntime)"),
            "{e}"
        );
        assert!(e.contains("--trust-plugins"), "{e}");
        assert!(check(&r, Trust::Config, &[]).is_ok());
    }

    #[test]
    fn plugin_libraries_are_listed_with_their_key() {
        let r = raw("");
        let lib = NamedLibrary {
            key: "[plugins] dirs".into(),
            path: PathBuf::from("p/libevil.so"),
        };
        let e = check(&r, Trust::Installed, std::slice::from_ref(&lib))
            .unwrap_err()
            .to_string();
        assert!(e.contains("p/libevil.so ([plugins] dirs)"), "{e}");
        assert!(check(&r, Trust::Config, &[lib]).is_ok());
    }
}
