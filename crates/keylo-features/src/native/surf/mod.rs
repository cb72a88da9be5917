//! `surf`: SURF (Bay, Ess, Tuytelaars, Van Gool, "Speeded-Up Robust Features", CVIU 2008),
//! written from the paper with OpenCV's documented defaults and layout (hessianThreshold 100,
//! 4 octaves, 3 layers, 64-d, not upright), so that it finds the keypoints OpenCV's non-free
//! SURF finds. Built only with the cargo feature `nonfree`: SURF was patented, and OpenCV
//! ships it only in its non-free build, so keylo does the same (docs/keypoints.md, "SURF").
//!
//! - [`haar`]: box filters on the integral image;
//! - [`hessian`]: the fast-Hessian detector;
//! - [`orientation`]: the dominant direction;
//! - [`descriptor`]: the 64-d (or 128-d) descriptor.

mod descriptor;
mod haar;
mod hessian;
mod orientation;

use keylo_core::{CoreError, DescriptorData, Descriptors, Detector, Image, Keypoint};

use super::input::one_plane;
use super::input::Plane;
use super::Integral;
use crate::classic::surf::SurfParams;
use crate::FeaturesError;
use descriptor::Describer;
use orientation::Disc;

/// The direction an upright keypoint is given, degrees (OpenCV's).
const UPRIGHT_ANGLE: f32 = 270.0;

/// SURF as a keylo detector and descriptor.
pub struct Surf {
    params: SurfParams,
    disc: Disc,
    describer: Describer,
}

impl Surf {
    /// Checks `params`.
    pub fn new(params: &SurfParams) -> Result<Self, FeaturesError> {
        crate::check(
            params.hessian_threshold.is_finite(),
            "hessian_threshold",
            params.hessian_threshold,
            "expected a finite number",
        )?;
        crate::check(
            (1..=8).contains(&params.n_octaves),
            "n_octaves",
            params.n_octaves,
            "expected 1..=8",
        )?;
        crate::check(
            (1..=16).contains(&params.n_octave_layers),
            "n_octave_layers",
            params.n_octave_layers,
            "expected 1..=16",
        )?;
        Ok(Self {
            params: params.clone(),
            disc: Disc::new(),
            describer: Describer::new(),
        })
    }

    fn dim(&self) -> usize {
        if self.params.extended {
            128
        } else {
            64
        }
    }

    /// Gives each keypoint its direction and, when `describe`, its descriptor; keypoints
    /// whose direction cannot be measured (too close to the border, too large for the image)
    /// are dropped, as OpenCV drops them.
    fn finish(
        &self,
        image: &Image,
        sat: &Integral,
        keypoints: &mut Vec<Keypoint>,
        describe: bool,
    ) -> Result<Option<Descriptors>, FeaturesError> {
        let plane = Plane::of(image);
        let mut values = Vec::new();
        let mut kept = Vec::with_capacity(keypoints.len());
        if image.width == 0 || image.height == 0 {
            keypoints.clear();
        }
        for mut k in keypoints.drain(..) {
            // A keypoint without a finite position or a positive size cannot be measured
            // (OpenCV would read outside the image).
            if !(k.x.is_finite() && k.y.is_finite() && k.size.is_finite() && k.size > 0.0) {
                continue;
            }
            let s = k.size * 1.2 / 9.0;
            let wavelet = 2 * i64::from(haar::round_even(2.0 * s));
            let (rows, cols) = (sat.height() as i64 + 1, sat.width() as i64 + 1);
            if rows < wavelet || cols < wavelet {
                continue;
            }
            let angle = if self.params.upright {
                None
            } else {
                match self.disc.direction(sat, (k.x, k.y), s, wavelet as i32) {
                    Some(a) => Some(a),
                    None => continue,
                }
            };
            k.angle = angle.unwrap_or(UPRIGHT_ANGLE);
            if describe {
                let extended = self.params.extended;
                self.describer
                    .describe(&plane, (k.x, k.y), s, angle, extended, &mut values)?;
            }
            kept.push(k);
        }
        *keypoints = kept;
        Ok(describe.then(|| Descriptors {
            rows: keypoints.len(),
            dim: self.dim(),
            data: DescriptorData::Float(values),
        }))
    }

    fn run(
        &self,
        image: &Image,
        describe: bool,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), FeaturesError> {
        one_plane("surf", image)?;
        let sat = Integral::new(image);
        let p = &self.params;
        let mut keypoints = hessian::detect(
            &sat,
            p.n_octaves as usize,
            p.n_octave_layers as usize,
            p.hessian_threshold as f32,
        );
        let d = self.finish(image, &sat, &mut keypoints, describe)?;
        Ok((keypoints, d))
    }
}

impl Detector for Surf {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        let (k, _) = self.run(image, false).map_err(|e| e.in_stage("detector"))?;
        Ok(k)
    }

    fn detect_and_describe(
        &mut self,
        image: &Image,
    ) -> Result<(Vec<Keypoint>, Option<Descriptors>), CoreError> {
        self.run(image, self.params.describe)
            .map_err(|e| e.in_stage("detector"))
    }
}

impl keylo_core::Descriptor for Surf {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        let err = |e: FeaturesError| e.in_stage("descriptor");
        one_plane("surf", image).map_err(err)?;
        let sat = Integral::new(image);
        let d = self.finish(image, &sat, keypoints, true).map_err(err)?;
        Ok(d.unwrap_or(Descriptors {
            rows: 0,
            dim: self.dim(),
            data: DescriptorData::Float(Vec::new()),
        }))
    }
}
