//! The source of a folder of PLY or PCD files: one file per frame, read when the frame is
//! asked for.

use std::path::{Path, PathBuf};

use keylo_core::{BuildContext, CoreError, ImageSource, LidarFrame, SourceInfo};

use super::config::{check_frame_rate, PointFilesConfig};
use crate::cloud::{RawCloud, Sensor};
use crate::folder::fields::{FieldInfo, FieldMap, FieldOptions};
use crate::folder::{frame_stamps, has_extension, has_files, list_files, FileSequence, Framer};
use crate::IoError;

/// The file format of a point-file folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointFormat {
    /// Stanford PLY (`.ply`).
    Ply,
    /// PCL's PCD (`.pcd`).
    Pcd,
}

impl PointFormat {
    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            PointFormat::Ply => "ply",
            PointFormat::Pcd => "pcd",
        }
    }

    /// Reads one file.
    pub fn read(
        self,
        path: &Path,
        stamp: f64,
        options: &FieldOptions,
    ) -> Result<RawCloud, IoError> {
        match self {
            PointFormat::Ply => crate::ply::read_ply(path, stamp, options),
            PointFormat::Pcd => crate::pcd::read_pcd(path, stamp, options),
        }
    }

    /// The fields of one file (its header).
    pub fn fields(self, path: &Path) -> Result<Vec<FieldInfo>, IoError> {
        match self {
            PointFormat::Ply => crate::ply::ply_fields(path),
            PointFormat::Pcd => crate::pcd::pcd_fields(path),
        }
    }

    /// True when `path` is a file of this format or a folder holding such files.
    pub fn probe(self, path: &Path) -> bool {
        let ext = [self.extension()];
        if path.is_dir() {
            has_files(path, &ext)
        } else {
            has_extension(path, &ext) && path.is_file()
        }
    }
}

/// Reads a folder of `.ply` or `.pcd` files (or one file) frame by frame.
pub struct PointFilesSource {
    format: PointFormat,
    files: FileSequence,
    framer: Framer,
    options: FieldOptions,
    description: String,
}

impl PointFilesSource {
    /// Opens the folder and reads the first selected file's header; errors name the folder,
    /// file or key that is wrong.
    pub fn open(
        format: PointFormat,
        config: &PointFilesConfig,
        ctx: &BuildContext,
    ) -> Result<Self, IoError> {
        let key = |m: String| IoError::format(Path::new("source"), m);
        let ext = format.extension();
        if config.path.is_empty() {
            return Err(key(format!(
                "no {ext} folder given: set `[source] path` or pass --data"
            )));
        }
        check_frame_rate(config.frame_rate_hz).map_err(key)?;
        let selection = config.selection().map_err(|e| key(e.to_string()))?;
        let framer =
            Framer::new(&config.projection, Sensor::Generic).map_err(|e| key(e.to_string()))?;
        let path = ctx.resolve_path(&config.path);
        let mut files = point_files(&path, ext)?;
        let (stamps, named) = frame_stamps(&mut files, config.frame_rate_hz);
        let files =
            FileSequence::new(files, stamps, &selection).map_err(|m| IoError::format(&path, m))?;
        let first = files.first().map(Path::to_path_buf).unwrap_or_default();
        let map = FieldMap::new(&format.fields(&first)?).map_err(|m| IoError::format(&first, m))?;
        let times = if named {
            "times from the file names".to_string()
        } else {
            format!("times index / {} Hz", config.frame_rate_hz)
        };
        let ignored = match map.ignored.as_slice() {
            [] => String::new(),
            names => format!("; fields not read: {}", names.join(", ")),
        };
        let description = format!(
            "{} files {} ({} of {} files; {times}{ignored})",
            ext.to_uppercase(),
            path.display(),
            files.selected(),
            files.total(),
        );
        Ok(Self {
            format,
            files,
            framer,
            options: config.field_options(),
            description,
        })
    }
}

/// The files of a folder (natural order) or the one file `path` names.
fn point_files(path: &Path, ext: &str) -> Result<Vec<PathBuf>, IoError> {
    if path.is_file() {
        if !has_extension(path, &[ext]) {
            return Err(IoError::format(path, format!("expected a .{ext} file")));
        }
        return Ok(vec![path.to_path_buf()]);
    }
    if !path.is_dir() {
        return Err(IoError::format(path, "no such file or folder"));
    }
    let files = list_files(path, &[ext])?;
    if files.is_empty() {
        return Err(IoError::format(
            path,
            format!("the folder holds no .{ext} file (expected one file per frame)"),
        ));
    }
    Ok(files)
}

impl ImageSource for PointFilesSource {
    fn info(&self) -> SourceInfo {
        SourceInfo {
            description: self.description.clone(),
            frames: Some(self.files.selected()),
        }
    }

    fn set_grid_needed(&mut self, needed: bool) {
        self.framer.set_grid_needed(needed);
    }

    fn frame_origin(&self, index: u64) -> Option<String> {
        self.files.path_of(index).map(|p| p.display().to_string())
    }

    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
        let entry = self.files.next_file()?;
        let path = entry.path;
        let frame = self
            .format
            .read(path, entry.stamp, &self.options)
            .and_then(|cloud| {
                self.framer
                    .frame(&cloud, entry.index as u64)
                    .map_err(|m| IoError::format(path, m))
            });
        Some(frame.map_err(CoreError::from))
    }
}
