//! The feature stages of one frame: its images, and each image's keypoints and descriptors
//! (side by side on rayon when every image has its own detector and descriptor).

use std::time::Instant;

use rayon::prelude::*;

use super::per_image::PerImage;
use super::result::StageTimings;
use super::Odometry;
use crate::stages::{Descriptor, Detector};
use crate::{ChannelFeatures, CoreError, FrameFeatures, LidarFrame};

impl Odometry {
    /// The images of `frame` and each one's keypoints and descriptors, timing the image,
    /// detect and describe stages into `timings`.
    pub(super) fn features(
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
