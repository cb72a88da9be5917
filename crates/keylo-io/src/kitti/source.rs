//! The source of a KITTI-style scan folder: one `.bin` scan per frame, read when the frame is
//! asked for; times from `times.txt`, ground truth from a pose file and `calib.txt`.

use std::path::{Path, PathBuf};

use keylo_core::{BuildContext, CoreError, ImageSource, LidarFrame, SourceInfo, Trajectory};

use super::config::KittiSourceConfig;
use super::ground_truth::lidar_ground_truth;
use super::side_files::{read_calib_tr, read_times};
use crate::cloud::{Sensor, VerticalAngleCorrection};
use crate::folder::{has_extension, index_stamps, list_files, FileSequence, Framer};
use crate::kitti_bin::read_kitti_cloud;
use crate::point_files::check_frame_rate;
use crate::IoError;

/// Where the scans of a KITTI path are and where to look for the side files.
struct Layout {
    scan_dir: PathBuf,
    scans: Vec<PathBuf>,
    /// Folders searched for times.txt, calib.txt and poses, in order; the first is the
    /// sequence folder (the base of `poses`).
    side_dirs: Vec<PathBuf>,
}

/// Reads a KITTI-style folder of `.bin` scans frame by frame.
pub struct KittiSource {
    files: FileSequence,
    framer: Framer,
    ground_truth: Option<Trajectory>,
    description: String,
}

impl KittiSource {
    /// Opens the folder and reads its side files; errors name the file, line or key that is
    /// wrong.
    pub fn open(config: &KittiSourceConfig, ctx: &BuildContext) -> Result<Self, IoError> {
        let key = |m: String| IoError::format(Path::new("source"), m);
        if config.path.is_empty() {
            return Err(key(
                "no KITTI folder given: set `[source] path` or pass --data".into(),
            ));
        }
        check_frame_rate(config.frame_rate_hz).map_err(key)?;
        let selection = config.selection().map_err(|e| key(e.to_string()))?;
        let correction = config.vertical_angle_correction_deg;
        if !(correction.is_finite() && correction.abs() <= 10.0) {
            return Err(key(format!(
                "`vertical_angle_correction_deg` = {correction}; expected -10..=10 degrees \
                 (KISS-ICP's KITTI loader: 0.205)"
            )));
        }
        let framer = Framer::new(&config.projection, Sensor::Hdl64e)
            .map_err(|e| key(e.to_string()))?
            .with_correction(VerticalAngleCorrection::new(correction));
        let layout = layout(&ctx.resolve_path(&config.path))?;
        let n = layout.scans.len();
        let times = layout.side_file("times.txt");
        let stamps = match &times {
            Some(p) => checked_times(p, &layout)?,
            None => index_stamps(n, config.frame_rate_hz),
        };
        let (ground_truth, gt_note) = ground_truth(config, &layout, &stamps)?;
        let files = FileSequence::new(layout.scans, stamps, &selection)
            .map_err(|m| IoError::format(&layout.scan_dir, m))?;
        let time_note = match times {
            Some(p) => format!("times from {}", p.display()),
            None => format!("times index / {} Hz", config.frame_rate_hz),
        };
        let description = format!(
            "KITTI scans {} ({} of {n} scans; {time_note}; {gt_note})",
            layout.scan_dir.display(),
            files.selected(),
        );
        Ok(Self {
            files,
            framer,
            ground_truth,
            description,
        })
    }
}

impl Layout {
    fn side_file(&self, name: &str) -> Option<PathBuf> {
        self.side_dirs
            .iter()
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    }
}

/// `DIR/velodyne/*.bin`, `DIR/*.bin` or one `.bin` file. Side files are looked up in the
/// sequence folder: `DIR`, and also the parent of a folder named `velodyne`.
fn layout(path: &Path) -> Result<Layout, IoError> {
    if path.is_file() {
        if !has_extension(path, &["bin"]) {
            return Err(IoError::format(path, "expected a .bin scan or a folder"));
        }
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        return Ok(Layout {
            scan_dir: dir.clone(),
            scans: vec![path.to_path_buf()],
            side_dirs: vec![dir],
        });
    }
    if !path.is_dir() {
        return Err(IoError::format(path, "no such file or folder"));
    }
    let velodyne = path.join("velodyne");
    let (scan_dir, mut side_dirs) = if velodyne.is_dir() {
        (velodyne, vec![path.to_path_buf()])
    } else {
        (path.to_path_buf(), vec![path.to_path_buf()])
    };
    if scan_dir == path && path.file_name().is_some_and(|n| n == "velodyne") {
        side_dirs.extend(path.parent().map(Path::to_path_buf));
    }
    let scans = list_files(&scan_dir, &["bin"])?;
    if scans.is_empty() {
        return Err(IoError::format(
            &scan_dir,
            "no .bin scans (expected velodyne/*.bin or *.bin, float32 x y z reflectance)",
        ));
    }
    Ok(Layout {
        scan_dir,
        scans,
        side_dirs,
    })
}

fn checked_times(path: &Path, layout: &Layout) -> Result<Vec<f64>, IoError> {
    let times = read_times(path)?;
    if times.len() != layout.scans.len() {
        return Err(IoError::format(
            path,
            format!(
                "{} times for {} scans in {}; expected one time per scan",
                times.len(),
                layout.scans.len(),
                layout.scan_dir.display()
            ),
        ));
    }
    Ok(times)
}

/// The LiDAR ground truth and a note for the description.
fn ground_truth(
    config: &KittiSourceConfig,
    layout: &Layout,
    stamps: &[f64],
) -> Result<(Option<Trajectory>, String), IoError> {
    let explicit = !config.poses.is_empty();
    let poses = if explicit {
        let base = layout.side_dirs.first().cloned().unwrap_or_default();
        let p = base.join(&config.poses);
        if !p.is_file() {
            return Err(IoError::format(&p, "`source.poses`: no such file"));
        }
        Some(p)
    } else {
        layout.side_file("poses.txt")
    };
    let Some(poses) = poses else {
        return Ok((None, "no ground truth".into()));
    };
    let tr = match layout.side_file("calib.txt") {
        Some(calib) => read_calib_tr(&calib)?,
        None => None,
    };
    match tr {
        Some(tr) => {
            let gt = lidar_ground_truth(&poses, &tr, stamps)?;
            let note = format!("ground truth {} in the LiDAR frame", poses.display());
            Ok((Some(gt), note))
        }
        None if explicit => Err(IoError::format(
            &poses,
            "cam0 poses need calib.txt with a `Tr:` line (Velodyne → cam0) beside the scans",
        )),
        None => Ok((
            None,
            format!(
                "{} not used: no calib.txt with a `Tr:` line",
                poses.display()
            ),
        )),
    }
}

impl ImageSource for KittiSource {
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
        let frame = read_kitti_cloud(path, entry.stamp).and_then(|cloud| {
            self.framer
                .frame(&cloud, entry.index as u64)
                .map_err(|m| IoError::format(path, m))
        });
        Some(frame.map_err(CoreError::from))
    }

    fn ground_truth(&self) -> Option<Trajectory> {
        self.ground_truth.clone()
    }
}

/// True when `path` is a `.bin` file, a folder with `velodyne/`, or a folder of `.bin` files.
pub fn is_kitti_data(path: &Path) -> bool {
    if path.is_file() {
        return has_extension(path, &["bin"]);
    }
    path.join("velodyne").is_dir() || crate::folder::has_files(path, &["bin"])
}
