//! Helpers shared by the integration tests: the real KITTI snippets (read in place, never
//! copied: their licence forbids it) and building sources through the registry.

#![allow(dead_code)]

pub mod fixtures;

use std::path::{Path, PathBuf};

use keylo_core::{BuildContext, CoreError, ImageSource, LidarFrame, Registry};

/// `shared/data/kitti_mini` beside the repository (or `$KEYLO_KITTI_MINI`), `None` with a
/// printed message when it is absent.
pub fn kitti_mini() -> Option<PathBuf> {
    let dir = std::env::var_os("KEYLO_KITTI_MINI").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/kitti_mini"),
        PathBuf::from,
    );
    if dir.join("00/velodyne/000000.bin").is_file() {
        Some(dir)
    } else {
        eprintln!(
            "skipped: the KITTI snippets are not at {} (set KEYLO_KITTI_MINI)",
            dir.display()
        );
        None
    }
}

/// A registry with keylo-io's sources.
pub fn registry() -> Registry {
    let mut r = Registry::default();
    keylo_io::register(&mut r);
    r
}

/// Builds source `kind` from TOML parameters (as `[source]` holds them, without `kind`).
pub fn build(kind: &str, params: &str) -> Result<Box<dyn ImageSource>, CoreError> {
    let table: toml::Table = toml::from_str(params).expect("test TOML");
    let r = registry();
    let factory = r.sources.get(kind).expect("registered kind");
    factory.build(&table, &BuildContext::default())
}

/// Every frame of `source`, stopping at the first error.
pub fn frames(source: &mut dyn ImageSource) -> Result<Vec<LidarFrame>, CoreError> {
    std::iter::from_fn(|| source.next_frame()).collect()
}

/// Reads `source` to its end: the frames read, then the error's text if one stopped it (and
/// nothing may follow an error).
pub fn read_until_error(source: &mut dyn ImageSource) -> (usize, Option<String>) {
    let mut ok = 0;
    while let Some(frame) = source.next_frame() {
        match frame {
            Ok(_) => ok += 1,
            Err(e) => {
                assert!(source.next_frame().is_none(), "nothing after an error");
                return (ok, Some(e.to_string()));
            }
        }
    }
    (ok, None)
}

/// Asserts that `err` mentions every one of `parts`.
pub fn assert_mentions(err: &str, parts: &[&str]) {
    for p in parts {
        assert!(err.contains(p), "`{p}` missing from: {err}");
    }
}

/// Writes `bytes` as `name` in a fresh temporary folder (removed when the guard drops).
pub fn temp_file(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temporary folder");
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).expect("write the copy");
    (dir, path)
}

/// TOML string literal of a path.
pub fn lit(path: &Path) -> String {
    format!("{:?}", path.display().to_string())
}

/// Writes KITTI `.bin` points (x y z reflectance, little-endian float32).
pub fn write_bin(path: &Path, points: &[[f32; 4]]) {
    let bytes: Vec<u8> = points
        .iter()
        .flat_map(|p| p.iter().flat_map(|v| v.to_le_bytes()))
        .collect();
    std::fs::write(path, bytes).expect("write .bin");
}
