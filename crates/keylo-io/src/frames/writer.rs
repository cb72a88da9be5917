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

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use keylo_core::{BuildContext, ImageSource};

    use super::*;
    use crate::frames::{FramesSource, FramesSourceConfig};

    /// A folder keeps the beams' column lags, so a destaggered Ouster frame read back has the
    /// same per-pixel times (and so the same deskewing) as when it was read from its capture.
    #[test]
    fn pixel_times_from_column_lags_survive_a_frame_folder() {
        let mut beams = BeamGeometry::unknown("test", 4);
        beams.altitude_deg = vec![1.0, 0.0, -1.0];
        beams.azimuth_deg = vec![0.0; 3];
        beams.column_lag_by_row = vec![0, 1, 3];
        let mut frame = LidarFrame::empty(0, 5.0, 3, 4, Arc::new(beams.clone()));
        frame.column_times = vec![5.0, 5.025, 5.05, 5.075];
        let dir = tempfile::tempdir().unwrap();
        let mut writer = FramesWriter::create(dir.path(), 3, 4, beams, "test").unwrap();
        writer.write(&frame).unwrap();
        writer.finish().unwrap();
        let config = FramesSourceConfig {
            path: dir.path().display().to_string(),
            ..FramesSourceConfig::default()
        };
        let ctx = BuildContext {
            base_dir: dir.path().to_path_buf(),
            ..Default::default()
        };
        let back = FramesSource::open(&config, &ctx)
            .unwrap()
            .next_frame()
            .unwrap()
            .unwrap();
        let times = |f: &LidarFrame| (0..12).map(|i| f.pixel_time(i)).collect::<Vec<_>>();
        assert_eq!(times(&back), times(&frame));
        assert_eq!(
            back.pixel_time(4),
            5.075,
            "row 1, column 0: column 3's time"
        );

        // A lag beyond the columns is refused, naming the field.
        let path = dir.path().join(MANIFEST);
        let text = std::fs::read_to_string(&path).unwrap();
        let bad = text.replace("\n      3\n", "\n      4\n");
        assert_ne!(bad, text);
        std::fs::write(&path, bad).unwrap();
        let e = FramesSource::open(&config, &ctx).err().unwrap();
        assert!(e.to_string().contains("column_lag_by_row"), "{e}");
    }
}
