//! `akaze` as keylo runs it: OpenCV's AKAZE, built per image size with only the scale levels
//! that can hold a keypoint on that size (`akaze_levels`), so the keypoints and descriptors
//! are OpenCV's defaults' and the levels that could never yield one are not computed.

use keylo_core::{CoreError, Descriptor, Descriptors, Detector, Image, Keypoint};

use super::akaze::{AkazeDescriptor, AkazeParams};
use super::akaze_levels::pruned;
use super::feature::CvFeature;
use crate::FeaturesError;

/// Image sizes kept at once (a pipeline has one or two; a resolution sweep more).
const MAX_SIZES: usize = 8;

/// The OpenCV object for one image size and how many scale levels it builds.
struct Sized {
    rows: usize,
    cols: usize,
    feature: CvFeature,
    levels: usize,
}

/// An AKAZE detector/descriptor computing only the scale levels each image size can use.
pub struct AkazeFeature {
    params: AkazeParams,
    /// The object with the parameters as given, for keypoints of levels a pruned one lacks.
    full: CvFeature,
    sized: Vec<Sized>,
}

impl AkazeFeature {
    /// Checks `params` by creating OpenCV's object for them.
    pub fn new(params: &AkazeParams) -> Result<Self, FeaturesError> {
        Ok(Self {
            full: CvFeature::new(params)?,
            params: params.clone(),
            sized: Vec::new(),
        })
    }

    /// The object for `image`'s size, made on first use.
    fn for_size(&mut self, image: &Image) -> Result<&mut Sized, FeaturesError> {
        let (rows, cols) = (image.height, image.width);
        if let Some(i) = self
            .sized
            .iter()
            .position(|s| (s.rows, s.cols) == (rows, cols))
        {
            return Ok(&mut self.sized[i]);
        }
        let p = &self.params;
        let kaze = matches!(
            p.descriptor_type,
            AkazeDescriptor::Kaze | AkazeDescriptor::KazeUpright
        );
        let (n_octaves, n_octave_layers, levels) =
            pruned(rows, cols, p.n_octaves, p.n_octave_layers, kaze);
        let feature = CvFeature::new(&AkazeParams {
            n_octaves,
            n_octave_layers,
            ..p.clone()
        })?;
        if self.sized.len() == MAX_SIZES {
            self.sized.remove(0);
        }
        self.sized.push(Sized {
            rows,
            cols,
            feature,
            levels,
        });
        let last = self.sized.len() - 1;
        Ok(&mut self.sized[last])
    }
}

impl Detector for AkazeFeature {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        let s = self.for_size(image).map_err(|e| e.in_stage("detector"))?;
        s.feature.detect(image)
    }

    fn detect_and_describe(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), CoreError> {
        let s = self.for_size(image).map_err(|e| e.in_stage("detector"))?;
        s.feature.detect_and_describe(image)
    }
}

impl Descriptor for AkazeFeature {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        let s = self.for_size(image).map_err(|e| e.in_stage("descriptor"))?;
        // AKAZE describes a keypoint on the level its class_id names: keypoints of a level
        // the pruned object does not build (from another detector's settings) need them all.
        let levels = s.levels;
        if keypoints
            .iter()
            .all(|k| usize::try_from(k.class_id).is_ok_and(|c| c < levels))
        {
            return s.feature.describe(image, keypoints);
        }
        self.full.describe(image, keypoints)
    }
}
