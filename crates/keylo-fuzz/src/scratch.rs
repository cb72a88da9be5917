//! A per-thread scratch folder for parsers that read files by path (in `/dev/shm` where it
//! exists, so writing an input costs little). It is emptied before every input.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

thread_local! {
    static DIR: RefCell<Option<tempfile::TempDir>> = const { RefCell::new(None) };
}

/// Runs `f` with an empty scratch folder, after writing `files` (relative path, bytes) into
/// it; folders in the paths are created. Empty files are written only when `keep_empty`.
pub fn with_files<R>(files: &[(&str, &[u8])], keep_empty: bool, f: impl FnOnce(&Path) -> R) -> R {
    DIR.with(|cell| {
        let mut slot = cell.borrow_mut();
        if slot.is_none() {
            *slot = Some(new_dir());
        }
        let dir = slot
            .as_ref()
            .map(|d| d.path().to_path_buf())
            .unwrap_or_default();
        clear(&dir);
        for (name, bytes) in files {
            if bytes.is_empty() && !keep_empty {
                continue;
            }
            let path = dir.join(name);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).expect("scratch folder is writable");
            }
            std::fs::write(&path, bytes).expect("scratch folder is writable");
        }
        f(&dir)
    })
}

fn new_dir() -> tempfile::TempDir {
    let shm = PathBuf::from("/dev/shm");
    let base = if shm.is_dir() {
        shm
    } else {
        std::env::temp_dir()
    };
    tempfile::Builder::new()
        .prefix("keylo-fuzz-")
        .tempdir_in(base)
        .or_else(|_| tempfile::tempdir())
        .expect("a temporary folder can be created")
}

fn clear(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for path in entries.filter_map(Result::ok).map(|e| e.path()) {
        let _ = if path.is_dir() {
            std::fs::remove_dir_all(&path)
        } else {
            std::fs::remove_file(&path)
        };
    }
}
