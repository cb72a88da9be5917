//! The files of a folder source that are read, with the time of each.

use std::path::{Path, PathBuf};

use crate::select::{FrameSelection, SelectionError};

/// One file to read: its index among the folder's files, its path and its time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FileEntry<'a> {
    /// Index among all files of the folder (the frame index).
    pub index: usize,
    /// The file.
    pub path: &'a Path,
    /// Frame time, seconds.
    pub stamp: f64,
}

/// The selected files of a folder, handed out one at a time.
#[derive(Debug, Clone, PartialEq)]
pub struct FileSequence {
    files: Vec<PathBuf>,
    stamps: Vec<f64>,
    selected: Vec<usize>,
    next: usize,
}

impl FileSequence {
    /// The files `selection` picks out of `files` (one stamp per file); the error says why
    /// none is selected.
    pub fn new(
        files: Vec<PathBuf>,
        stamps: Vec<f64>,
        selection: &FrameSelection,
    ) -> Result<Self, SelectionError> {
        if stamps.len() != files.len() {
            return Err(SelectionError::StampCount {
                stamps: stamps.len(),
                files: files.len(),
            });
        }
        let selected = selection.indices(files.len())?;
        Ok(Self {
            files,
            stamps,
            selected,
            next: 0,
        })
    }

    /// Number of files in the folder.
    pub fn total(&self) -> usize {
        self.files.len()
    }

    /// Number of files selected.
    pub fn selected(&self) -> usize {
        self.selected.len()
    }

    /// The first selected file.
    pub fn first(&self) -> Option<&Path> {
        let i = *self.selected.first()?;
        self.files.get(i).map(PathBuf::as_path)
    }

    /// The file of frame `index` (its index among the folder's files).
    pub fn path_of(&self, index: u64) -> Option<&Path> {
        let i = usize::try_from(index).ok()?;
        self.files.get(i).map(PathBuf::as_path)
    }

    /// The next selected file, `None` after the last.
    pub fn next_file(&mut self) -> Option<FileEntry<'_>> {
        let index = *self.selected.get(self.next)?;
        self.next += 1;
        Some(FileEntry {
            index,
            path: self.files.get(index)?,
            stamp: self.stamps.get(index).copied()?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hands_out_the_selected_files_with_their_stamps() {
        let files: Vec<PathBuf> = (0..5).map(|i| PathBuf::from(format!("{i}.bin"))).collect();
        let stamps = vec![0.0, 0.1, 0.2, 0.3, 0.4];
        let sel = FrameSelection::new(1, 2, 0).unwrap();
        let mut s = FileSequence::new(files.clone(), stamps.clone(), &sel).unwrap();
        assert_eq!((s.total(), s.selected()), (5, 2));
        let e = s.next_file().unwrap();
        assert_eq!((e.index, e.stamp), (1, 0.1));
        assert_eq!(s.next_file().unwrap().path, Path::new("3.bin"));
        assert!(s.next_file().is_none());
        let late = FrameSelection::new(9, 1, 0).unwrap();
        assert!(FileSequence::new(files, stamps, &late)
            .unwrap_err()
            .to_string()
            .contains("source.start"));
    }
}
