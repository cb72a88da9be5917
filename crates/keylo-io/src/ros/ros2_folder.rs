//! ROS2 bag folders: `metadata.yaml` beside the storage file, an `.mcap` (storage `mcap`, the
//! default since Iron) or a `.db3` (storage `sqlite3`, the default of Foxy and Humble).

use std::path::{Path, PathBuf};

use crate::IoError;

/// The storage plugins keylo reads, with the extension of their files.
const STORAGES: [(&str, &str); 2] = [("mcap", "mcap"), ("sqlite3", "db3")];

/// True for a ROS2 bag folder keylo reads: `metadata.yaml` and one storage file.
pub(crate) fn is_bag_folder(dir: &Path) -> bool {
    dir.join("metadata.yaml").is_file() && storage_file(dir).is_ok()
}

/// The storage file of a ROS2 bag folder: the one file of the storage `metadata.yaml` names
/// (`storage_identifier`), or when it names none the one `.mcap` or `.db3` file.
pub(crate) fn storage_file(dir: &Path) -> Result<PathBuf, IoError> {
    let entries = std::fs::read_dir(dir).map_err(|e| IoError::io(dir, e))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    paths.sort();
    let with_ext = |ext: &str| -> Vec<&PathBuf> {
        paths
            .iter()
            .filter(|p| p.extension().is_some_and(|x| x == ext))
            .collect()
    };
    let storage = storage_identifier(dir);
    let ext = match storage.as_deref() {
        Some(id) => extension_of(id).ok_or_else(|| {
            IoError::format(
                &dir.join("metadata.yaml"),
                format!("storage_identifier `{id}`: keylo reads storage `mcap` and `sqlite3`"),
            )
        })?,
        None if with_ext("mcap").is_empty() && !with_ext("db3").is_empty() => "db3",
        None => "mcap",
    };
    match with_ext(ext).as_slice() {
        [one] => Ok((*one).clone()),
        [] => Err(IoError::format(
            dir,
            no_file(&paths, ext, storage.is_some()),
        )),
        many => Err(IoError::format(
            dir,
            format!(
                "the folder holds {} .{ext} files (a split bag); give one file as the path",
                many.len()
            ),
        )),
    }
}

fn extension_of(storage: &str) -> Option<&'static str> {
    STORAGES
        .iter()
        .find(|(id, _)| *id == storage)
        .map(|(_, ext)| *ext)
}

/// Why no storage file was found.
fn no_file(paths: &[PathBuf], ext: &str, named: bool) -> String {
    let compressed = format!(".{ext}.zstd");
    if paths
        .iter()
        .any(|p| p.to_string_lossy().ends_with(&compressed))
    {
        return format!(
            "a file-compressed bag ({compressed}): decompress it first \
             (`ros2 bag decompress`, or `zstd -d` on the file)"
        );
    }
    if named {
        format!("the folder holds no .{ext} file (the storage metadata.yaml names)")
    } else {
        "the folder holds no .mcap or .db3 file".to_string()
    }
}

/// `storage_identifier` of the folder's `metadata.yaml`, when it is readable and says.
fn storage_identifier(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join("metadata.yaml")).ok()?;
    text.lines().find_map(|line| {
        let value = line.trim().strip_prefix("storage_identifier:")?;
        let value = value.trim().trim_matches(|c| c == '\'' || c == '"');
        (!value.is_empty()).then(|| value.to_string())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(metadata: &str, files: &[&str]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("metadata.yaml"), metadata).unwrap();
        for f in files {
            std::fs::write(dir.path().join(f), b"").unwrap();
        }
        dir
    }

    fn name(dir: &tempfile::TempDir) -> String {
        let file = storage_file(dir.path()).unwrap();
        file.file_name().unwrap().to_string_lossy().into_owned()
    }

    fn error(dir: &tempfile::TempDir) -> String {
        storage_file(dir.path()).unwrap_err().to_string()
    }

    #[test]
    fn the_storage_metadata_names_picks_the_file() {
        let yaml = "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n";
        let dir = folder(yaml, &["b_0.db3", "other.mcap"]);
        assert_eq!(name(&dir), "b_0.db3");
        assert!(is_bag_folder(dir.path()));
        let dir = folder("  storage_identifier: 'mcap'\n", &["b_0.db3", "b_0.mcap"]);
        assert_eq!(name(&dir), "b_0.mcap");
        // Unstated storage: the one .mcap, else the one .db3.
        assert_eq!(name(&folder("x", &["a.db3"])), "a.db3");
        assert_eq!(name(&folder("x", &["a.mcap"])), "a.mcap");
    }

    #[test]
    fn folders_without_one_readable_file_say_why() {
        let e = error(&folder("storage_identifier: sqlite3", &["a.mcap"]));
        assert!(e.contains("no .db3 file"), "{e}");
        let e = error(&folder("storage_identifier: sqlite3", &["a_0.db3.zstd"]));
        assert!(
            e.contains("file-compressed") && e.contains(".db3.zstd"),
            "{e}"
        );
        let e = error(&folder("storage_identifier: cloud", &["a.db3"]));
        assert!(e.contains("metadata.yaml") && e.contains("`cloud`"), "{e}");
        let e = error(&folder(
            "storage_identifier: sqlite3",
            &["a_0.db3", "a_1.db3"],
        ));
        assert!(e.contains("2 .db3 files (a split bag)"), "{e}");
        let dir = folder("x", &[]);
        assert!(error(&dir).contains("no .mcap or .db3 file"));
        assert!(!is_bag_folder(dir.path()));
        let plain = tempfile::tempdir().unwrap();
        std::fs::write(plain.path().join("a.db3"), b"").unwrap();
        assert!(!is_bag_folder(plain.path()), "metadata.yaml is required");
    }
}
