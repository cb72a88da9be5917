//! Composes the stages: [`Odometry`] turns frames into poses; [`Pipeline`] adds the source.

mod build;
mod features;
mod guarded;
mod paced;
mod per_image;
mod prefetch;
mod result;

use std::time::Instant;

pub use build::build_source;
pub use paced::Paced;
pub use per_image::PerImage;
pub use prefetch::Prefetched;
pub use result::{FrameResult, StageTimings};

use crate::config::PipelineConfig;
use crate::stages::{Descriptor, Detector, Downsampler, ImageBuilder, ImageSource, Registrar};
use crate::{BuildContext, CoreError, FrameFeatures, LidarFrame, Pose, Registry};
use build::{build_optional, build_stage};

/// The per-frame stages, without a source: embed this to feed frames yourself.
///
/// Thread-safety: `Odometry` is `Send` but not `Sync`: move it to any thread, use it from one
/// thread at a time (every method that changes state takes `&mut self`, so the compiler
/// enforces it). Its stages may use rayon's pool (or their own) inside a call.
pub struct Odometry {
    pub image: Option<Box<dyn ImageBuilder>>,
    pub detector: PerImage<dyn Detector>,
    pub descriptor: PerImage<dyn Descriptor>,
    pub downsampler: Box<dyn Downsampler>,
    pub registrar: Box<dyn Registrar>,
    /// Whether the per-image overrides were checked against the images of a first frame.
    checked_images: bool,
    /// The cloud of the last registered frame (kept for embedders, e.g. the C API).
    last_cloud: Option<crate::PointCloud>,
    /// Timestamp of the last registered frame: frames must come in time order.
    last_timestamp: Option<f64>,
}

impl Odometry {
    /// Builds the per-frame stages of a resolved config.
    pub fn build(config: &PipelineConfig, registry: &Registry) -> Result<Self, CoreError> {
        let ctx = BuildContext {
            base_dir: config.base_dir.clone(),
            trust: config.trust,
        };
        let image = build_optional(&registry.images, "image", &config.image, &ctx)?;
        let names = image.as_ref().map(|b| b.image_names()).unwrap_or_default();
        let odometry = Self {
            image,
            detector: PerImage::build(
                &registry.detectors,
                "detector",
                &config.detector,
                &ctx,
                &names,
            )?,
            descriptor: PerImage::build(
                &registry.descriptors,
                "descriptor",
                &config.descriptor,
                &ctx,
                &names,
            )?,
            downsampler: build_stage(
                &registry.downsamplers,
                "downsampler",
                &config.downsampler,
                &ctx,
            )?,
            registrar: build_stage(&registry.registrars, "registrar", &config.registrar, &ctx)?,
            checked_images: false,
            last_cloud: None,
            last_timestamp: None,
        };
        if odometry.detector.any() && odometry.image.is_none() {
            return Err(CoreError::stage(
                "detector",
                "a detector needs images: set `[image] kind` to an image builder",
            ));
        }
        Ok(odometry)
    }

    /// Whether any stage reads the image grid of a frame (images, pixel windows, keypoint
    /// points); when none does, unorganised sources may skip building it
    /// ([`ImageSource::set_grid_needed`]).
    pub fn needs_grid(&self) -> bool {
        self.image.is_some() || self.downsampler.needs_grid() || self.registrar.wants_keypoints()
    }

    /// SLAM hook: the motion from the last frame to the next (e.g. from an IMU), used by the
    /// registrar instead of its motion model for the next frame only
    /// ([`Registrar::set_motion_prior`]); an error when the registrar does not offer it or
    /// the transform is not rigid.
    pub fn set_motion_prior(&mut self, delta: &Pose) -> Result<(), CoreError> {
        self.registrar.set_motion_prior(delta)
    }

    /// SLAM hook: starts over: the registrar forgets its map and motion, and the next frame
    /// may have any time stamp ([`Registrar::reset`]).
    pub fn reset(&mut self) -> Result<(), CoreError> {
        self.registrar.reset()?;
        self.last_timestamp = None;
        self.last_cloud = None;
        Ok(())
    }

    /// SLAM hook: the last frame's pose becomes `pose`; the map and motion are kept
    /// ([`Registrar::set_pose`]).
    pub fn set_pose(&mut self, pose: &Pose) -> Result<(), CoreError> {
        self.registrar.set_pose(pose)
    }

    /// SLAM hook: the registrar's local map, world frame (empty when it does not expose one).
    pub fn local_map(&self) -> Vec<nalgebra::Point3<f64>> {
        self.registrar.local_map()
    }

    /// The cloud the downsampler gave the registrar for the last frame processed, in the
    /// sensor frame (not deskewed); `None` before the first frame.
    pub fn last_cloud(&self) -> Option<&crate::PointCloud> {
        self.last_cloud.as_ref()
    }

    /// Runs every stage on one frame.
    pub fn process(&mut self, frame: &LidarFrame) -> Result<FrameResult, CoreError> {
        self.process_with_features(frame).map(|(result, _)| result)
    }

    /// [`Odometry::process`], also returning the images, keypoints and descriptors the
    /// feature stages made (empty without an image builder), e.g. for a loop-closure module;
    /// [`crate::keypoint_points`] places them in 3-D.
    pub fn process_with_features(
        &mut self,
        frame: &LidarFrame,
    ) -> Result<(FrameResult, FrameFeatures), CoreError> {
        frame.check_shape().map_err(|e| CoreError::BadFrame {
            frame: frame.index,
            message: e.to_string(),
        })?;
        self.check_time_order(frame)?;
        let mut timings = StageTimings::default();
        let features = self
            .features(frame, &mut timings)
            .map_err(|e| in_frame(e, frame.index))?;
        let t = Instant::now();
        let cloud = self
            .downsampler
            .downsample(frame, &features)
            .map_err(|e| in_frame(e, frame.index))?;
        timings.downsample = t.elapsed().as_secs_f64();
        if cloud.is_empty() && !self.registrar.accepts_empty_clouds() {
            return Err(CoreError::BadFrame {
                frame: frame.index,
                message: match &frame.scan {
                    Some(scan) => format!(
                        "no point to register (the scan holds {} finite points; the \
                         downsampler kept none)",
                        scan.len()
                    ),
                    None => format!(
                        "no valid finite point to register ({} valid pixels of {})",
                        frame.valid_count(),
                        frame.rows * frame.cols
                    ),
                },
            });
        }
        let t = Instant::now();
        let registered = if self.registrar.wants_keypoints() {
            let keypoints = crate::FrameKeypoints::from_features(frame, &features);
            self.registrar.register_with_keypoints(&cloud, &keypoints)
        } else {
            self.registrar.register(&cloud)
        };
        let reg = registered.map_err(|e| in_frame(e, frame.index))?;
        timings.register = t.elapsed().as_secs_f64();
        let cloud_points = cloud.len();
        self.last_cloud = Some(cloud);
        self.last_timestamp = Some(frame.timestamp);
        let result = FrameResult {
            index: frame.index,
            stamp: frame.end_stamp(),
            pose: reg.pose,
            keypoints: features.keypoint_count(),
            cloud_points,
            registered_points: reg.source_points,
            map_points: self.registrar.map_size(),
            iterations: reg.iterations,
            converged: reg.converged,
            degenerate: crate::Degenerate::of(
                reg.source_points,
                self.registrar.min_points(),
                reg.degeneracy.as_ref(),
            ),
            degeneracy: reg.degeneracy,
            fit: reg.fit,
            timings,
        };
        Ok((result, features))
    }

    /// A frame whose timestamp is not finite, or not after the last registered frame's (time
    /// going backwards, or the same frame twice), is a bad frame: the motion model and
    /// deskew assume time order.
    fn check_time_order(&self, frame: &LidarFrame) -> Result<(), CoreError> {
        let t = frame.timestamp;
        let message = if !t.is_finite() {
            format!("timestamp {t} s is not finite")
        } else {
            match self.last_timestamp {
                Some(prev) if t <= prev => format!(
                    "timestamp {t:.6} s is not after the previous frame's {prev:.6} s \
                     (time going backwards, or the same frame twice)"
                ),
                _ => return Ok(()),
            }
        };
        Err(CoreError::BadFrame {
            frame: frame.index,
            message,
        })
    }
}

/// A stage error of frame `index`, naming it (other errors already name what they concern).
fn in_frame(e: CoreError, index: u64) -> CoreError {
    match e {
        CoreError::Stage { stage, message } => CoreError::Stage {
            stage,
            message: format!("frame {index}: {message}"),
        },
        other => other,
    }
}

/// A source plus the per-frame stages: iterate it to run odometry.
pub struct Pipeline {
    pub source: Box<dyn ImageSource>,
    pub odometry: Odometry,
}

impl Pipeline {
    /// Builds every stage of a resolved config.
    pub fn build(config: &PipelineConfig, registry: &Registry) -> Result<Self, CoreError> {
        let mut source = build_source(config, registry)?;
        let odometry = Odometry::build(config, registry)?;
        source.set_grid_needed(odometry.needs_grid());
        Ok(Self { source, odometry })
    }

    /// Reads and processes the next frame; `None` at the end of the source.
    pub fn step(&mut self) -> Option<Result<FrameResult, CoreError>> {
        let frame = match self.source.next_frame()? {
            Ok(f) => f,
            Err(e) => return Some(Err(e)),
        };
        Some(self.odometry.process(&frame))
    }
}
