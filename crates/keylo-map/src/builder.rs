//! Builds a map folder while a run goes: each registered frame's points enter the tiled
//! global cloud in the world frame; keyframes are written as they are chosen; `finish`
//! writes the cloud files and `map.json`.

use std::path::{Path, PathBuf};

use keylo_core::voxel::downsample_indices;
use keylo_core::{FrameFeatures, FrameResult, LidarFrame, Pose};
use keylo_io::export::{write_xyzi, CloudFormat};
use keylo_registration::kiss_icp::deskew::deskew;
use nalgebra::Point3;

use crate::features_json::features_json;
use crate::keyframes::{keyframe_file, KeyframeLog, KeyframePolicy, KeyframeRow};
use crate::manifest::{files, Bounds, MapManifest, FORMAT, VERSION};
use crate::tiles::TiledCloud;
use crate::{MapConfig, MapError};

/// Builds one map folder from the frames of a run, in order.
pub struct MapBuilder {
    dir: PathBuf,
    config: MapConfig,
    source: String,
    cloud: TiledCloud,
    keyframes: KeyframeLog,
    policy: KeyframePolicy,
    keyframe_count: usize,
    wrote_features: bool,
    last_pose: Option<Pose>,
    frames: usize,
}

impl MapBuilder {
    /// Starts a map in `dir` (created; the keyframes of an earlier map there are removed)
    /// for a run of `source` (its description, kept in `map.json`).
    pub fn create(dir: &Path, config: MapConfig, source: &str) -> Result<Self, MapError> {
        config.check().map_err(|message| MapError::Config {
            origin: dir.display().to_string(),
            message,
        })?;
        std::fs::create_dir_all(dir).map_err(|e| MapError::io(dir, e))?;
        let old = dir.join(files::KEYFRAME_DIR);
        if old.is_dir() {
            std::fs::remove_dir_all(&old).map_err(|e| MapError::io(&old, e))?;
        }
        let scratch = dir.join(".tiles");
        if scratch.is_dir() {
            std::fs::remove_dir_all(&scratch).map_err(|e| MapError::io(&scratch, e))?;
        }
        Ok(Self {
            cloud: TiledCloud::new(
                config.voxel_size,
                config.tile_size,
                config.max_range,
                config.voxel_budget(),
                &scratch,
            )?,
            keyframes: KeyframeLog::create(dir)?,
            policy: KeyframePolicy::new(config.keyframe_distance, config.keyframe_angle_deg),
            dir: dir.to_path_buf(),
            config,
            source: source.to_string(),
            keyframe_count: 0,
            wrote_features: false,
            last_pose: None,
            frames: 0,
        })
    }

    /// The map's settings.
    pub fn config(&self) -> &MapConfig {
        &self.config
    }

    /// Adds a registered frame (its result from the odometry, and the features the
    /// pipeline made of it, if any); returns whether it became a keyframe.
    pub fn add(
        &mut self,
        frame: &LidarFrame,
        result: &FrameResult,
        features: Option<&FrameFeatures>,
    ) -> Result<bool, MapError> {
        let (points, intensities) = self.sensor_points(frame, &result.pose);
        let world: Vec<Point3<f64>> = points.iter().map(|p| result.pose * p).collect();
        self.cloud.add(&world, &intensities)?;
        let sensor = Point3::from(result.pose.translation.vector);
        self.cloud.spill_far_from(&sensor)?;
        self.last_pose = Some(result.pose);
        self.frames += 1;
        if !self.policy.take(&result.pose) {
            return Ok(false);
        }
        let k = self.keyframe_count;
        let keep = match self.config.keyframe_voxel_size {
            0.0 => (0..points.len()).collect(),
            size => downsample_indices(&points, size),
        };
        let path = keyframe_file(&self.dir, k, "ply");
        let rows = keep.iter().map(|&i| {
            let p = points[i];
            [p.x as f32, p.y as f32, p.z as f32, intensities[i]]
        });
        let comment = format!(
            "keylo map keyframe {k}: frame {}, sensor frame at the scan's end",
            frame.index
        );
        write_xyzi(&path, CloudFormat::Ply, keep.len(), &comment, rows)?;
        let mut keypoints = 0;
        if self.config.keyframe_features {
            if let Some(json) = features.and_then(|f| features_json(frame, f)) {
                let path = keyframe_file(&self.dir, k, "features.json");
                let text = serde_json::to_string(&json).map_err(|e| MapError::format(&path, e))?;
                std::fs::write(&path, text).map_err(|e| MapError::io(&path, e))?;
                keypoints = features.map_or(0, FrameFeatures::keypoint_count);
                self.wrote_features = true;
            }
        }
        self.keyframes.push(&KeyframeRow {
            keyframe: k,
            frame: frame.index,
            stamp: result.stamp,
            pose: result.pose,
            points: keep.len(),
            keypoints,
        })?;
        self.keyframe_count += 1;
        Ok(true)
    }

    /// The frame's points in the sensor frame (deskewed to the scan's end with the motion
    /// from the previous pose when set and possible) within the range limits, with their
    /// intensities.
    fn sensor_points(&self, frame: &LidarFrame, pose: &Pose) -> (Vec<Point3<f64>>, Vec<f32>) {
        let cloud = frame.to_cloud();
        let mut points = cloud.points;
        if let (true, Some(times), Some(last)) = (self.config.deskew, &cloud.times, &self.last_pose)
        {
            deskew(&mut points, times, &(last.inverse() * pose));
        }
        let intensities = cloud.intensities.unwrap_or_else(|| vec![0.0; points.len()]);
        let (min, max) = (self.config.min_range, self.config.max_range);
        points
            .into_iter()
            .zip(intensities)
            .filter(|(p, _)| {
                let r = p.coords.norm();
                r.is_finite() && r > min && r < max
            })
            .unzip()
    }

    /// Writes the global cloud (`map.ply`, `map.pcd`) and `map.json`; returns the manifest.
    /// Memory: one tile at a time.
    pub fn finish(mut self) -> Result<MapManifest, MapError> {
        self.cloud.spill_all()?;
        let n = self.cloud.len();
        let mut bounds = Bounds::empty();
        let comment =
            "keylo map: the run's voxelised cloud, world frame (x y z metres, mean intensity)";
        for (name, format) in [
            (files::CLOUD_PLY, CloudFormat::Ply),
            (files::CLOUD_PCD, CloudFormat::Pcd),
        ] {
            let path = self.dir.join(name);
            write_cloud(&self.cloud, (&path, format), n, comment, &mut bounds)?;
        }
        self.cloud.remove_scratch()?;
        let manifest = MapManifest {
            format: FORMAT.into(),
            version: VERSION,
            keylo_version: env!("CARGO_PKG_VERSION").into(),
            frame: "world: the odometry's frame (the first pose)".into(),
            settings: self.config.clone(),
            frames: self.frames,
            points: n,
            bounds: (n > 0).then_some(bounds),
            keyframes: self.keyframe_count,
            keyframe_features: self.wrote_features,
            source: self.source.clone(),
            cropped_from: None,
        };
        manifest.write(&self.dir)?;
        tracing::info!(
            "map: {} points from {} frames, {} keyframes, in {} (at most {} voxels in memory)",
            n,
            self.frames,
            self.keyframe_count,
            self.dir.display(),
            self.cloud.peak_resident_voxels
        );
        Ok(manifest)
    }
}

/// Writes the `n` voxels of `cloud` to `path` in `format`, one tile at a time, growing
/// `bounds` to hold them.
fn write_cloud(
    cloud: &TiledCloud,
    (path, format): (&Path, CloudFormat),
    n: usize,
    comment: &str,
    bounds: &mut Bounds,
) -> Result<(), MapError> {
    let mut failed = None;
    let rows = cloud
        .rows()
        .flat_map(|tile| {
            tile.unwrap_or_else(|e| {
                failed.get_or_insert(e);
                Vec::new()
            })
        })
        .inspect(|r| bounds.grow([f64::from(r[0]), f64::from(r[1]), f64::from(r[2])]));
    let written = write_xyzi(path, format, n, comment, rows);
    match failed {
        Some(e) => Err(e),
        None => Ok(written?),
    }
}
