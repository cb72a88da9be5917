//! Where plugin libraries are looked for: `[plugins] dirs`, `KEYLO_PLUGIN_PATH`, then the
//! default install folder.

use std::path::{Path, PathBuf};

use crate::PluginError;

/// The environment variable holding extra plugin folders (`:`-separated on Unix).
pub const PLUGIN_PATH_ENV: &str = "KEYLO_PLUGIN_PATH";

/// Where a folder named by a config's `[plugins] dirs` came from.
pub const CONFIG_DIRS: &str = "[plugins] dirs";

/// The default install folder below the home directory.
pub const DEFAULT_DIR: &str = ".local/lib/keylo/plugins";

/// An ordered list of folders, each with where it came from (for messages).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SearchPath {
    pub dirs: Vec<(PathBuf, &'static str)>,
}

impl SearchPath {
    /// `config_dirs` (already resolved), then `KEYLO_PLUGIN_PATH`, then `~/.local/lib/keylo/plugins`.
    pub fn new(config_dirs: &[PathBuf]) -> Self {
        let mut dirs: Vec<(PathBuf, &'static str)> = config_dirs
            .iter()
            .map(|d| (d.clone(), CONFIG_DIRS))
            .collect();
        if let Some(v) = std::env::var_os(PLUGIN_PATH_ENV) {
            dirs.extend(
                std::env::split_paths(&v)
                    .filter(|p| !p.as_os_str().is_empty())
                    .map(|p| (p, PLUGIN_PATH_ENV)),
            );
        }
        if let Some(home) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
            dirs.push((Path::new(&home).join(DEFAULT_DIR), "default"));
        }
        Self { dirs }
    }

    /// The library file of plugin `name`: the first folder holding one of [`file_names`].
    pub fn find(&self, name: &str) -> Result<PathBuf, PluginError> {
        self.find_with_origin(name).map(|(path, _)| path)
    }

    /// [`SearchPath::find`] with where the folder came from (`[plugins] dirs`,
    /// `KEYLO_PLUGIN_PATH`, `default`).
    pub fn find_with_origin(&self, name: &str) -> Result<(PathBuf, &'static str), PluginError> {
        let files = file_names(name);
        for (dir, from) in &self.dirs {
            for f in &files {
                let path = dir.join(f);
                // Only a file directly in the folder (a name with a path in it never is).
                if path.is_file() && path.parent() == Some(dir.as_path()) {
                    return Ok((path, from));
                }
            }
        }
        let searched = if self.dirs.is_empty() {
            "no folder (set [plugins] dirs or KEYLO_PLUGIN_PATH)".to_string()
        } else {
            self.dirs
                .iter()
                .map(|(d, from)| format!("{} ({from})", d.display()))
                .collect::<Vec<_>>()
                .join("; ")
        };
        Err(PluginError::NotFound {
            name: name.into(),
            files: files.join(", "),
            searched,
        })
    }

    /// Every shared library in the searched folders, in search order (for `keylo plugins list`).
    pub fn libraries(&self) -> Vec<PathBuf> {
        self.libraries_with_origin()
            .into_iter()
            .map(|(p, _)| p)
            .collect()
    }

    /// [`SearchPath::libraries`], each with where its folder came from.
    pub fn libraries_with_origin(&self) -> Vec<(PathBuf, &'static str)> {
        let mut out = Vec::new();
        for (dir, from) in &self.dirs {
            let Ok(entries) = std::fs::read_dir(dir) else {
                continue;
            };
            let mut found: Vec<PathBuf> = entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && is_library(p))
                .collect();
            found.sort();
            out.extend(found.into_iter().map(|p| (p, *from)));
        }
        out
    }
}

/// The file names plugin `name` may have: `libNAME.so` and `NAME.so` (platform prefix and
/// suffix), also with `-` written `_` as cargo names its libraries.
pub fn file_names(name: &str) -> Vec<String> {
    let (pre, suf) = (std::env::consts::DLL_PREFIX, std::env::consts::DLL_SUFFIX);
    let mut stems = vec![name.to_string()];
    if name.contains('-') {
        stems.push(name.replace('-', "_"));
    }
    let mut out = Vec::new();
    for s in &stems {
        if !pre.is_empty() {
            out.push(format!("{pre}{s}{suf}"));
        }
        out.push(format!("{s}{suf}"));
    }
    out
}

fn is_library(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.ends_with(std::env::consts::DLL_SUFFIX))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_cover_prefix_and_dashes() {
        let n = file_names("range-edges");
        if cfg!(target_os = "linux") {
            assert_eq!(
                n,
                [
                    "librange-edges.so",
                    "range-edges.so",
                    "librange_edges.so",
                    "range_edges.so"
                ]
            );
        }
    }

    #[test]
    fn not_found_lists_every_folder() {
        let s = SearchPath {
            dirs: vec![
                (PathBuf::from("/nonexistent/a"), "[plugins] dirs"),
                (PathBuf::from("/nonexistent/b"), PLUGIN_PATH_ENV),
            ],
        };
        let e = s.find("x").err().map(|e| e.to_string()).unwrap_or_default();
        assert!(
            e.contains("/nonexistent/a ([plugins] dirs); /nonexistent/b (KEYLO_PLUGIN_PATH)"),
            "{e}"
        );
    }
}
