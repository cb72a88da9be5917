//! Finding and loading the ONNX Runtime shared library, once per process.
//!
//! keylo links ONNX Runtime dynamically (`ort`'s `load-dynamic`), so a keylo binary without
//! SuperPoint in its config never needs the library, and a missing library is a clear error
//! that lists where it was looked for, not a panic.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

use ort::environment::Environment;

use crate::FeaturesError;

/// The loaded library and its environment (ONNX Runtime allows one per process).
struct Loaded {
    path: PathBuf,
    environment: Environment,
}

static LOADED: OnceLock<Loaded> = OnceLock::new();
static LOADING: Mutex<()> = Mutex::new(());

/// The process's ONNX Runtime environment, loading the library on first use from `explicit`
/// (a config path, may be empty) or the default places.
pub fn environment(explicit: &str) -> Result<&'static Environment, FeaturesError> {
    let _guard = LOADING.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(loaded) = LOADED.get() {
        if !explicit.is_empty() && Path::new(explicit) != loaded.path {
            return Err(FeaturesError::Unavailable(format!(
                "`onnxruntime` = \"{explicit}\": ONNX Runtime is already loaded from `{}` \
                 in this process (one library per process; use the same path everywhere)",
                loaded.path.display()
            )));
        }
        return Ok(&loaded.environment);
    }
    let path = find_library(explicit)?;
    let environment = ort::init_from(&path)
        .map_err(|e| FeaturesError::Unavailable(format!("ONNX Runtime: {e}")))?
        .with_name("keylo")
        .build()
        .map_err(|e| {
            FeaturesError::Unavailable(format!("ONNX Runtime from `{}`: {e}", path.display()))
        })?;
    tracing::info!("loaded ONNX Runtime from {}", path.display());
    Ok(&LOADED
        .get_or_init(|| Loaded { path, environment })
        .environment)
}

/// The path of the library in use, once loaded.
pub fn loaded_library() -> Option<&'static Path> {
    LOADED.get().map(|l| l.path.as_path())
}

/// The library file: `explicit`, else the first found in [`search_dirs`].
pub fn find_library(explicit: &str) -> Result<PathBuf, FeaturesError> {
    if !explicit.is_empty() {
        let p = PathBuf::from(explicit);
        return if p.is_file() {
            Ok(p)
        } else {
            Err(FeaturesError::Unavailable(format!(
                "`onnxruntime` = \"{explicit}\": no such file (expected the path of \
                 libonnxruntime.so.1.x)"
            )))
        };
    }
    let mut searched = Vec::new();
    for var in ["KEYLO_ONNXRUNTIME", "ORT_DYLIB_PATH"] {
        if let Some(v) = std::env::var_os(var).filter(|v| !v.is_empty()) {
            let p = PathBuf::from(&v);
            if p.is_file() {
                return Ok(p);
            }
            if let Some(found) = library_in(&p) {
                return Ok(found);
            }
            searched.push(format!("${var} = {}", p.display()));
        }
    }
    for dir in search_dirs() {
        if let Some(found) = library_in(&dir) {
            return Ok(found);
        }
        searched.push(dir.display().to_string());
    }
    Err(FeaturesError::Unavailable(format!(
        "SuperPoint needs the ONNX Runtime library (libonnxruntime.so.1.x), found in none of: \
         {}. Run `bash scripts/setup.sh` (it takes the library from the PyPI `onnxruntime` \
         wheel), or set `onnxruntime = \"/path/libonnxruntime.so.1.x\"` in the stage or \
         $KEYLO_ONNXRUNTIME",
        searched.join(", ")
    )))
}

/// Folders searched after the environment variables: beside the executable (and its
/// `../lib`), then the repository's `.cache/onnxruntime/` where `scripts/setup.sh` puts it.
pub fn search_dirs() -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    if let Some(exe_dir) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(Path::to_path_buf))
    {
        dirs.push(exe_dir.join("lib"));
        dirs.push(exe_dir.join("../lib"));
        dirs.push(exe_dir.clone());
        // target/{release,debug}/ (and deps/ for tests) of a checkout.
        for up in ["../..", "../../.."] {
            dirs.push(exe_dir.join(up).join(".cache/onnxruntime"));
        }
    }
    dirs.push(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../.cache/onnxruntime"));
    dirs
}

/// The newest `libonnxruntime.so*` (or `.dylib`/`.dll`) file in `dir`.
fn library_in(dir: &Path) -> Option<PathBuf> {
    let entries = std::fs::read_dir(dir).ok()?;
    let mut found: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.is_file()
                && p.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                    n.starts_with("libonnxruntime.so")
                        || n == "libonnxruntime.dylib"
                        || n == "onnxruntime.dll"
                })
        })
        .collect();
    found.sort();
    found.pop()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_explicit_library_is_named() {
        let e = find_library("/nonexistent/libonnxruntime.so.1.32.0")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("onnxruntime") && e.contains("/nonexistent"),
            "{e}"
        );
    }

    #[test]
    fn finds_the_newest_library_in_a_folder() {
        let dir = std::env::temp_dir().join(format!("keylo-ort-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for n in [
            "libonnxruntime.so.1.20.0",
            "libonnxruntime.so.1.32.0",
            "other.so",
        ] {
            std::fs::write(dir.join(n), b"").unwrap();
        }
        let found = library_in(&dir).unwrap();
        assert!(found.ends_with("libonnxruntime.so.1.32.0"), "{found:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
