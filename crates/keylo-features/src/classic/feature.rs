//! One OpenCV `Feature2D` as a keylo [`Detector`] and [`Descriptor`].

use keylo_core::{CoreError, Descriptor, Descriptors, Detector, Image, Keypoint};
use opencv::core::{no_array, KeyPoint, Mat, Ptr, Vector};
use opencv::features2d::Feature2D;
use opencv::prelude::*;

use crate::cv::{from_cv_keypoints, to_cv_keypoints, to_descriptors, to_mat};
use crate::FeaturesError;

/// An OpenCV detector/extractor made from a parameter struct.
pub trait CvParams {
    /// The backend kind, for messages.
    const KIND: &'static str;
    /// Whether the algorithm computes descriptors (FAST and GFTT do not).
    const DESCRIBES: bool;
    /// The OpenCV object, after checking the parameters.
    fn create(&self) -> Result<Ptr<Feature2D>, FeaturesError>;
    /// Whether `detect_and_describe` should also compute descriptors in the same pass.
    fn describe_in_detector(&self) -> bool {
        false
    }
    /// The highest keypoint octave the extractor can describe (ORB builds one pyramid level
    /// per octave it is given), `None`: any.
    fn max_octave(&self) -> Option<i32> {
        None
    }
}

/// An OpenCV `Feature2D` behind keylo's stage traits.
pub struct CvFeature {
    kind: &'static str,
    inner: Ptr<Feature2D>,
    describes: bool,
    describe_in_detector: bool,
    max_octave: Option<i32>,
}

impl CvFeature {
    /// Creates the OpenCV object of `params`.
    pub fn new<P: CvParams>(params: &P) -> Result<Self, FeaturesError> {
        Ok(Self {
            kind: P::KIND,
            inner: params.create()?,
            describes: P::DESCRIBES,
            describe_in_detector: P::DESCRIBES && params.describe_in_detector(),
            max_octave: params.max_octave(),
        })
    }

    fn gray(&self, image: &Image) -> Result<Mat, FeaturesError> {
        if image.channels != 1 {
            return Err(FeaturesError::BadInput(format!(
                "`{}` needs a one-plane image; image `{}` has {} planes \
                 (two-plane images are for SuperPoint)",
                self.kind,
                image.name(),
                image.channels
            )));
        }
        to_mat(image)
    }

    fn run_detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, FeaturesError> {
        let mat = self.gray(image)?;
        let mut kps = Vector::<KeyPoint>::new();
        self.inner
            .detect(&mat, &mut kps, &no_array())
            .map_err(|e| FeaturesError::opencv(format!("{} detect", self.kind), e))?;
        Ok(from_cv_keypoints(&kps))
    }

    fn run_detect_and_compute(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Descriptors), FeaturesError> {
        let mat = self.gray(image)?;
        let mut kps = Vector::<KeyPoint>::new();
        let mut desc = Mat::default();
        self.inner
            .detect_and_compute(&mat, &no_array(), &mut kps, &mut desc, false)
            .map_err(|e| FeaturesError::opencv(format!("{} detectAndCompute", self.kind), e))?;
        Ok((from_cv_keypoints(&kps), to_descriptors(&desc)?))
    }

    fn run_compute(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, FeaturesError> {
        if !self.describes {
            return Err(FeaturesError::Unavailable(format!(
                "`{}` detects keypoints but computes no descriptors",
                self.kind
            )));
        }
        if let Some(max) = self.max_octave {
            if let Some(k) = keypoints.iter().find(|k| k.octave < 0 || k.octave > max) {
                return Err(FeaturesError::BadInput(format!(
                    "`{}` describes keypoints of pyramid octaves 0–{max} only, got octave {} \
                     (SIFT packs octave and layer into it): use keypoints of ORB or of a \
                     single-scale detector (FAST, Shi-Tomasi, Harris, SuperPoint), or another \
                     descriptor",
                    self.kind, k.octave
                )));
            }
        }
        let mat = self.gray(image)?;
        let mut kps = to_cv_keypoints(keypoints)?;
        let mut desc = Mat::default();
        self.inner
            .compute(&mat, &mut kps, &mut desc)
            .map_err(|e| FeaturesError::opencv(format!("{} compute", self.kind), e))?;
        *keypoints = from_cv_keypoints(&kps);
        let d = to_descriptors(&desc)?;
        if d.rows != keypoints.len() {
            return Err(FeaturesError::BadInput(format!(
                "`{}` returned {} descriptors for {} keypoints",
                self.kind,
                d.rows,
                keypoints.len()
            )));
        }
        Ok(d)
    }
}

impl Detector for CvFeature {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        self.run_detect(image).map_err(|e| e.in_stage("detector"))
    }

    fn detect_and_describe(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), CoreError> {
        if !self.describe_in_detector {
            return Ok((self.detect(image)?, None));
        }
        let (k, d) = self
            .run_detect_and_compute(image)
            .map_err(|e| e.in_stage("detector"))?;
        Ok((k, Some(d)))
    }
}

impl Descriptor for CvFeature {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        self.run_compute(image, keypoints)
            .map_err(|e| e.in_stage("descriptor"))
    }
}
