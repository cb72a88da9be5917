//! Per-frame results written as they are made: `trajectory.tum`, `trajectory.kitti` and
//! `frames.csv` get one line per registered frame, flushed at once, so a run that is killed
//! from outside (SIGKILL, the out-of-memory killer, a power cut) still leaves every frame it
//! finished on disk. `summary.json` is written once, at the end.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use keylo::io::trajectory::{
    format_kitti_line, format_kitti_line_exact, format_tum_line, format_tum_line_exact,
};
use keylo::Pose;

use crate::report::{FrameRow, FRAMES_CSV_HEADER};

/// One output file being appended to.
struct Stream {
    path: PathBuf,
    file: BufWriter<File>,
}

impl Stream {
    fn create(path: PathBuf, header: Option<&str>) -> Result<Self> {
        let file = File::create(&path).with_context(|| format!("creating {}", path.display()))?;
        let mut s = Self {
            path,
            file: BufWriter::new(file),
        };
        if let Some(h) = header {
            s.append(&format!("{h}\n"))?;
        }
        Ok(s)
    }

    fn append(&mut self, text: &str) -> Result<()> {
        self.file
            .write_all(text.as_bytes())
            .and_then(|()| self.file.flush())
            .with_context(|| format!("writing {}", self.path.display()))
    }
}

/// The per-frame output files of one run.
pub struct Journal {
    tum: Option<Stream>,
    kitti: Option<Stream>,
    frames: Stream,
    /// Trajectory numbers in their shortest exact form (`[output] exact`).
    exact: bool,
}

impl Journal {
    /// Creates (truncates) the files in `dir`; the trajectory files only where asked for.
    pub fn create(dir: &Path, output: &keylo::config::OutputConfig) -> Result<Self> {
        let (tum, kitti) = (output.tum, output.kitti);
        let stream = |name: &str| Stream::create(dir.join(name), None);
        Ok(Self {
            tum: tum.then(|| stream("trajectory.tum")).transpose()?,
            kitti: kitti.then(|| stream("trajectory.kitti")).transpose()?,
            frames: Stream::create(dir.join("frames.csv"), Some(FRAMES_CSV_HEADER))?,
            exact: output.exact,
        })
    }

    /// Appends one registered frame to every file.
    pub fn record(&mut self, stamp: f64, pose: &Pose, row: &FrameRow) -> Result<()> {
        if let Some(s) = &mut self.tum {
            s.append(&if self.exact {
                format_tum_line_exact(stamp, pose)
            } else {
                format_tum_line(stamp, pose)
            })?;
        }
        if let Some(s) = &mut self.kitti {
            s.append(&if self.exact {
                format_kitti_line_exact(pose)
            } else {
                format_kitti_line(pose)
            })?;
        }
        self.frames.append(&row.csv_line())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_frame_is_on_disk_as_soon_as_it_is_recorded() {
        let dir = tempfile::tempdir().unwrap();
        let mut j = Journal::create(dir.path(), &keylo::config::OutputConfig::default()).unwrap();
        let row = FrameRow {
            frame: 0,
            stamp: 0.1,
            keypoints: 5,
            cloud_points: 100,
            registered_points: 90,
            map_points: 400,
            odometry_ms: 12.5,
            rss_mb: Some(70.0),
            degenerate: None,
        };
        j.record(0.1, &Pose::translation(1.0, 2.0, 3.0), &row)
            .unwrap();
        // Still open: what a killed process would leave behind.
        let read = |n: &str| std::fs::read_to_string(dir.path().join(n)).unwrap();
        assert_eq!(read("trajectory.tum").lines().count(), 1);
        assert_eq!(read("trajectory.kitti").lines().count(), 1);
        assert_eq!(
            read("frames.csv"),
            format!("{FRAMES_CSV_HEADER}\n0,0.100000,5,100,90,400,12.500,70.0,\n")
        );
        let mut traj = keylo::Trajectory::default();
        traj.push(0.1, Pose::translation(1.0, 2.0, 3.0));
        assert_eq!(
            read("trajectory.tum"),
            keylo::io::trajectory::format_tum(&traj)
        );
        drop(j);
    }
}
