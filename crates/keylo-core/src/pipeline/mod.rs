//! Composes the stages: [`Odometry`] turns frames into poses; [`Pipeline`] adds the source.

mod guarded;
mod paced;
mod per_image;
mod prefetch;

use std::time::Instant;

use rayon::prelude::*;

pub use paced::Paced;
pub use per_image::PerImage;
pub use prefetch::Prefetched;

use crate::config::{PipelineConfig, StageConfig};
use crate::registry::Backends;
use crate::stages::{Descriptor, Detector, Downsampler, ImageBuilder, ImageSource, Registrar};
use crate::{BuildContext, ChannelFeatures, CoreError, FrameFeatures, LidarFrame, Pose, Registry};

/// Seconds spent in each stage for one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings {
    pub image: f64,
    pub detect: f64,
    pub describe: f64,
    pub downsample: f64,
    pub register: f64,
}

impl StageTimings {
    /// Sum over stages.
    pub fn total(&self) -> f64 {
        self.image + self.detect + self.describe + self.downsample + self.register
    }
}

/// The result of one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameResult {
    pub index: u64,
    /// Time the pose refers to, seconds: the frame's end ([`LidarFrame::end_stamp`]), the same
    /// whichever points the downsampler kept.
    pub stamp: f64,
    pub pose: Pose,
    /// Keypoints found over all images.
    pub keypoints: usize,
    /// Points the downsampler passed to the registrar.
    pub cloud_points: usize,
    /// Points the registrar used after its own preprocessing.
    pub registered_points: usize,
    /// Points in the registrar's local map after this frame.
    pub map_points: usize,
    pub iterations: usize,
    pub converged: bool,
    /// The registrar's degeneracy analysis of this frame, when it makes one.
    pub degeneracy: Option<crate::Degeneracy>,
    /// Why the registration could not constrain the pose, when it could not (too few points,
    /// a direction without information): the pose is then (partly) the prediction.
    pub degenerate: Option<crate::Degenerate>,
    /// How well the frame fits the prior map, when the registrar localises in one.
    pub fit: Option<crate::MapFit>,
    pub timings: StageTimings,
}

impl FrameResult {
    /// The result of a frame whose pose came from elsewhere (ground truth, another odometry):
    /// for a [`FrameResult`]-taking consumer such as a map builder; counts zero, no
    /// degeneracy analysis.
    pub fn with_pose(index: u64, stamp: f64, pose: Pose) -> Self {
        Self {
            index,
            stamp,
            pose,
            keypoints: 0,
            cloud_points: 0,
            registered_points: 0,
            map_points: 0,
            iterations: 0,
            converged: true,
            degeneracy: None,
            degenerate: None,
            fit: None,
            timings: StageTimings::default(),
        }
    }
}

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

fn build_stage<T: ?Sized + 'static>(
    backends: &Backends<T>,
    section: &str,
    stage: &StageConfig,
    ctx: &BuildContext,
) -> Result<Box<T>, CoreError> {
    let factory = backends.get(&stage.kind).ok_or_else(|| {
        CoreError::stage(
            section,
            format!("backend `{}` is not registered", stage.kind),
        )
    })?;
    factory.build(&stage.params, ctx)
}

pub(crate) fn build_optional<T: ?Sized + 'static>(
    backends: &Backends<T>,
    section: &str,
    stage: &StageConfig,
    ctx: &BuildContext,
) -> Result<Option<Box<T>>, CoreError> {
    if stage.is_none() {
        return Ok(None);
    }
    build_stage(backends, section, stage, ctx).map(Some)
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

    fn features(
        &mut self,
        frame: &LidarFrame,
        timings: &mut StageTimings,
    ) -> Result<FrameFeatures, CoreError> {
        let mut features = FrameFeatures::default();
        let Some(builder) = self.image.as_mut() else {
            return Ok(features);
        };
        let t = Instant::now();
        let images = builder.build(frame)?;
        timings.image = t.elapsed().as_secs_f64();
        if !self.checked_images {
            self.check_image_names(&images)?;
        }
        let names: Vec<String> = images.iter().map(crate::Image::name).collect();
        let parallel = images.len() > 1
            && self.detector.has_own_instances(&names)
            && self.descriptor.has_own_instances(&names);
        let t = Instant::now();
        let results: Vec<Result<Extracted, CoreError>> = if parallel {
            let detectors = self.detector.instances_for(&names);
            let descriptors = self.descriptor.instances_for(&names);
            images
                .into_par_iter()
                .zip(detectors)
                .zip(descriptors)
                .map(|((image, det), desc)| extract(image, det, desc))
                .collect()
        } else {
            images
                .into_iter()
                .map(|image| {
                    let name = image.name();
                    let det = self.detector.for_image(&name);
                    extract_one(image, det, &mut self.descriptor, &name)
                })
                .collect()
        };
        let wall = t.elapsed().as_secs_f64();
        let (mut detect, mut describe) = (0.0, 0.0);
        for r in results {
            let e = r?;
            detect += e.detect_s;
            describe += e.describe_s;
            features.per_image.push(e.features);
        }
        // Images ran side by side: split the section's wall time in proportion.
        let busy = detect + describe;
        if busy > 0.0 {
            timings.detect = wall * detect / busy;
            timings.describe = wall * describe / busy;
        }
        Ok(features)
    }

    /// Every `by_image` override must name an image the image builder makes.
    fn check_image_names(&mut self, images: &[crate::Image]) -> Result<(), CoreError> {
        let names: Vec<String> = images.iter().map(crate::Image::name).collect();
        let unknown = [
            ("detector", self.detector.unknown_images(&names)),
            ("descriptor", self.descriptor.unknown_images(&names)),
        ];
        for (section, list) in unknown {
            if let Some(image) = list.first() {
                return Err(CoreError::stage(
                    section,
                    format!(
                        "`[{section}.by_image.{image}]` names no image; the image builder makes: {}",
                        names.join(", ")
                    ),
                ));
            }
        }
        self.checked_images = true;
        Ok(())
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

/// One image's keypoints and descriptors, with the seconds each step took.
struct Extracted {
    features: ChannelFeatures,
    detect_s: f64,
    describe_s: f64,
}

/// Detects (and describes) the keypoints of one image.
fn extract(
    image: crate::Image,
    detector: Option<&mut (dyn Detector + 'static)>,
    descriptor: Option<&mut (dyn Descriptor + 'static)>,
) -> Result<Extracted, CoreError> {
    let t = Instant::now();
    let (mut keypoints, mut descriptors) = match detector {
        Some(d) => d.detect_and_describe(&image)?,
        None => (Vec::new(), None),
    };
    let detect_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    if let Some(d) = descriptor {
        descriptors = Some(d.describe(&image, &mut keypoints)?);
    }
    Ok(Extracted {
        features: ChannelFeatures {
            image,
            keypoints,
            descriptors,
        },
        detect_s,
        describe_s: t.elapsed().as_secs_f64(),
    })
}

/// [`extract`] with the descriptor looked up by image name (sequential path).
fn extract_one(
    image: crate::Image,
    detector: Option<&mut (dyn Detector + 'static)>,
    descriptors: &mut PerImage<dyn Descriptor>,
    name: &str,
) -> Result<Extracted, CoreError> {
    extract(image, detector, descriptors.for_image(name))
}

/// Builds only the source of a resolved config (for tools that read data without running
/// odometry: `keylo info`, `keylo convert`).
pub fn build_source(
    config: &PipelineConfig,
    registry: &Registry,
) -> Result<Box<dyn ImageSource>, CoreError> {
    let ctx = BuildContext {
        base_dir: config.base_dir.clone(),
        trust: config.trust,
    };
    build_stage(&registry.sources, "source", &config.source, &ctx)
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
