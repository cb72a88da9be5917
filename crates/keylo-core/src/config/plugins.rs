use serde::{Deserialize, Serialize};

/// `[plugins]`: where run-time plugins (`kind = "plugin:NAME"`) are looked for.
///
/// A plugin `NAME` is the shared library `libNAME.so` (or `NAME.so`; `-` in the name may be
/// `_` in the file name, as cargo writes it). The folders are searched in this order: `dirs`,
/// then the folders of the `KEYLO_PLUGIN_PATH` environment variable, then
/// `~/.local/lib/keylo/plugins`. See docs/plugins.md.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PluginsConfig {
    /// Folders searched first for plugin libraries; relative folders are resolved against the
    /// config file's folder.
    pub dirs: Vec<String>,
}

impl PluginsConfig {
    /// `dirs` resolved against `base_dir` (the config file's folder).
    pub fn dir_paths(&self, base_dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        self.dirs
            .iter()
            .map(|d| {
                let p = std::path::Path::new(d);
                if p.is_absolute() {
                    p.to_path_buf()
                } else {
                    base_dir.join(p)
                }
            })
            .collect()
    }
}
