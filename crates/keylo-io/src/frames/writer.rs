use std::path::{Path, PathBuf};

use keylo_core::{BeamGeometry, LidarFrame};

use super::{codec, Manifest, FRAMES_DIR, MANIFEST};
use crate::IoError;

/// Writes frames into a keylo frame folder; [`FramesWriter::finish`] writes the manifest.
pub struct FramesWriter {
    dir: PathBuf,
    manifest: Manifest,
}

impl FramesWriter {
    /// Creates `dir/frames/` for frames of the given shape.
    pub fn create(
        dir: &Path,
        rows: usize,
        cols: usize,
        beams: BeamGeometry,
        description: &str,
    ) -> Result<Self, IoError> {
        let frames = dir.join(FRAMES_DIR);
        std::fs::create_dir_all(&frames).map_err(|e| IoError::io(&frames, e))?;
        // A folder written before holds frames of its own: remove them (and only them) so the
        // new manifest and the frame files agree.
        crate::remove_files_with_extension(&frames, "klf")?;
        Ok(Self {
            dir: dir.to_path_buf(),
            manifest: Manifest {
                format: "keylo-frames".into(),
                version: 1,
                rows,
                cols,
                frames: 0,
                beams,
                description: description.into(),
            },
        })
    }

    /// Appends one frame (its shape must match the folder's).
    pub fn write(&mut self, frame: &LidarFrame) -> Result<(), IoError> {
        let path = self
            .dir
            .join(FRAMES_DIR)
            .join(format!("{:06}.klf", self.manifest.frames));
        if frame.rows != self.manifest.rows || frame.cols != self.manifest.cols {
            return Err(IoError::format(
                &path,
                format!(
                    "frame is {}x{}, folder is {}x{}",
                    frame.rows, frame.cols, self.manifest.rows, self.manifest.cols
                ),
            ));
        }
        std::fs::write(&path, codec::encode(frame)).map_err(|e| IoError::io(&path, e))?;
        self.manifest.frames += 1;
        Ok(())
    }

    /// Writes the manifest; returns the number of frames.
    pub fn finish(self) -> Result<usize, IoError> {
        let path = self.dir.join(MANIFEST);
        let text = serde_json::to_string_pretty(&self.manifest)
            .map_err(|e| IoError::format(&path, e.to_string()))?;
        std::fs::write(&path, text).map_err(|e| IoError::io(&path, e))?;
        Ok(self.manifest.frames)
    }
}
