//! `freak`: the FREAK binary descriptor (Alahi, Ortiz, Vandergheynst, CVPR 2012), native.
//!
//! With `pattern = "opencv"` (default) it computes OpenCV contrib's FREAK descriptors bit
//! for bit ([`super::freak_cv`]). With `pattern = "trained"`, keylo's own: the retina pattern ([`super::freak_pattern`]) is scaled by `pattern_scale` × the keypoint's
//! scale (its size / 7, within `n_octaves` octaves, when `scale_normalized`), each receptive
//! field is averaged over its square from an integral image (the nearest whole-pixel square for
//! fields of half-width ≥ 1.5 px, area-weighted for smaller ones), the orientation
//! is the paper's mean of the 45 orientation pairs' intensity differences along their unit
//! vectors, the pattern is turned by it (when `orientation_normalized`) and sampled again,
//! and bit `k` is 1 when field `a` of pair `k` is brighter than field `b`.

use keylo_core::{CoreError, Descriptor, Descriptors, Image, Keypoint};
use serde::{Deserialize, Serialize};

use super::freak_cv::CvFreak;
use super::freak_pairs::SELECTED_PAIRS;
use super::freak_pattern::{
    extent, orientation_pairs, retina, Field, DESCRIPTOR_PAIRS, FIELDS, ORIENTATION_PAIRS,
    SMALLEST_KEYPOINT_SIZE,
};
use super::input::{binary, one_plane, Plane};
use super::Integral;
use crate::{check, FeaturesError};

/// Fields of at least this half-width (pixels) are averaged over the nearest whole-pixel
/// square (an edge moves ≤ ½ px, a third of the half-width); smaller ones area-weighted.
const ROUNDED_FROM: f32 = 1.5;

/// Fields the orientation pairs use (the five outer rings).
const ORIENTATION_FIELDS: usize = 30;

/// Bytes per FREAK descriptor (512 bits).
pub const FREAK_BYTES: usize = DESCRIPTOR_PAIRS / 8;

/// `[descriptor] kind = "freak"` (the defaults of OpenCV contrib's `FREAK`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct FreakParams {
    /// Turn the pattern by the orientation FREAK estimates (and store it as the keypoint's
    /// angle, degrees).
    pub orientation_normalized: bool,
    /// Scale the pattern with the keypoint's size (size 7 px = scale 1); otherwise every
    /// keypoint is described at scale 1.
    pub scale_normalized: bool,
    /// Radius of the pattern's outermost extent at scale 1, pixels.
    pub pattern_scale: f32,
    /// Octaves of keypoint scale covered: scales are clamped to `1 ..= 2^n_octaves`.
    pub n_octaves: i32,
    /// `opencv` (OpenCV contrib's FREAK, bit for bit) or `trained` (keylo's own sampling and
    /// its own 512 pairs, trained on LiDAR images).
    pub pattern: FreakPattern,
}

/// Which FREAK `freak` computes.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum FreakPattern {
    /// OpenCV contrib's: its quantised pattern, integer field means and its 512 pairs.
    #[default]
    Opencv,
    /// keylo's own: continuous scales and angles, float means, pairs trained on LiDAR images.
    Trained,
}

impl Default for FreakParams {
    fn default() -> Self {
        Self {
            orientation_normalized: true,
            scale_normalized: true,
            pattern_scale: 22.0,
            n_octaves: 4,
            pattern: FreakPattern::Opencv,
        }
    }
}

/// The native FREAK descriptor.
pub struct Freak {
    params: FreakParams,
    opencv: Option<CvFreak>,
    fields: [Field; FIELDS],
    orientation: [(usize, usize, f32, f32); ORIENTATION_PAIRS],
}

impl Freak {
    /// Checks `params` and lays out the pattern.
    pub fn new(params: &FreakParams) -> Result<Self, FeaturesError> {
        let ps = params.pattern_scale;
        check(
            ps.is_finite() && ps > 0.0 && ps <= 1000.0,
            "pattern_scale",
            ps,
            "expected a number > 0 and at most 1000 (pixels)",
        )?;
        check(
            (1..=8).contains(&params.n_octaves),
            "n_octaves",
            params.n_octaves,
            "expected 1 ..= 8",
        )?;
        let fields = retina();
        debug_assert!(orientation_pairs()
            .iter()
            .all(|&(i, j)| usize::from(i.max(j)) < ORIENTATION_FIELDS));
        let orientation = orientation_pairs().map(|(i, j)| {
            let (a, b) = (fields[i as usize], fields[j as usize]);
            let (dx, dy) = (a.x - b.x, a.y - b.y);
            let n = (dx * dx + dy * dy).sqrt();
            (i as usize, j as usize, dx / n, dy / n)
        });
        let opencv = (params.pattern == FreakPattern::Opencv).then(|| {
            CvFreak::new(
                params.pattern_scale,
                params.n_octaves,
                params.scale_normalized,
                params.orientation_normalized,
            )
        });
        Ok(Self {
            params: params.clone(),
            opencv,
            fields,
            orientation,
        })
    }

    /// Pattern scale of `kp` (1 for keypoints of size 7 px or less).
    fn scale(&self, kp: &Keypoint) -> f32 {
        let max = 2f32.powi(self.params.n_octaves);
        let s = kp.size / SMALLEST_KEYPOINT_SIZE;
        if self.params.scale_normalized && s.is_finite() {
            s.clamp(1.0, max)
        } else {
            1.0
        }
    }

    /// Mean intensities of the first `n` of the 43 fields around `(x, y)` (the rest 0), the
    /// pattern scaled by `px` pixels per unit and turned by `(sin, cos)`.
    fn sample(
        &self,
        sat: &Integral,
        (x, y): (f32, f32),
        px: f32,
        n: usize,
        (s, c): (f32, f32),
    ) -> [f32; FIELDS] {
        let mut out = [0.0; FIELDS];
        for (v, f) in out.iter_mut().zip(&self.fields).take(n) {
            let (fx, fy) = (f.x * px, f.y * px);
            let (fx, fy, half) = (x + c * fx - s * fy, y + s * fx + c * fy, f.sigma * px);
            *v = if half >= ROUNDED_FROM {
                sat.rounded_box_mean(fx, fy, half)
            } else {
                sat.area_mean(fx, fy, half)
            };
        }
        out
    }

    /// Orientation in degrees, `[0, 360)`, from the unturned pattern's intensities.
    fn orientation_of(&self, v: &[f32; FIELDS]) -> f32 {
        let (mut ox, mut oy) = (0f32, 0f32);
        for &(i, j, ux, uy) in &self.orientation {
            let d = v[i] - v[j];
            ox += d * ux;
            oy += d * uy;
        }
        let a = oy.atan2(ox).to_degrees();
        if a < 0.0 {
            a + 360.0
        } else {
            a
        }
    }

    /// The 43 field intensities of `kp` with the pattern as the descriptor uses it (scaled,
    /// turned), updating `kp.angle` when orientation-normalised; `None` when the pattern
    /// leaves the image. The pair training uses this.
    pub fn field_values(&self, sat: &Integral, kp: &mut Keypoint) -> Option<[f32; FIELDS]> {
        let px = self.scale(kp) * self.params.pattern_scale / extent();
        // The pattern plus a margin of one pixel strictly inside the image (the keypoints
        // OpenCV's FREAK keeps, too; the fields themselves would fit 1.5 px closer).
        let m = (extent() * px).ceil() + 1.0;
        let (w, h) = (sat.width() as f32, sat.height() as f32);
        if !(kp.x > m && kp.y > m && kp.x < w - m && kp.y < h - m) {
            return None;
        }
        let at = (kp.x, kp.y);
        if !self.params.orientation_normalized {
            return Some(self.sample(sat, at, px, FIELDS, (0.0, 1.0)));
        }
        // The orientation pairs use the five outer rings only.
        let upright = self.sample(sat, at, px, ORIENTATION_FIELDS, (0.0, 1.0));
        kp.angle = self.orientation_of(&upright);
        Some(self.sample(sat, at, px, FIELDS, kp.angle.to_radians().sin_cos()))
    }

    /// Descriptors of `keypoints`, dropping those whose pattern leaves the image.
    pub fn compute(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, FeaturesError> {
        one_plane("freak", image)?;
        let sat = Integral::new(image);
        let mut data = Vec::with_capacity(keypoints.len() * FREAK_BYTES);
        if let Some(cv) = &self.opencv {
            let plane = Plane::of(image);
            keypoints.retain_mut(|kp| cv.describe(&plane, &sat, kp, &mut data));
            return Ok(binary(FREAK_BYTES, data));
        }
        keypoints.retain_mut(|kp| {
            let Some(v) = self.field_values(&sat, kp) else {
                return false;
            };
            // Bit k of the row is pair k, most significant bit of each byte first.
            data.extend(SELECTED_PAIRS.chunks_exact(8).map(|pairs| {
                pairs.iter().fold(0u8, |byte, &(a, b)| {
                    (byte << 1) | u8::from(v[a as usize] > v[b as usize])
                })
            }));
            true
        });
        Ok(binary(FREAK_BYTES, data))
    }
}

impl Descriptor for Freak {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        self.compute(image, keypoints)
            .map_err(|e| e.in_stage("descriptor"))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_images::{blobs, hamming, keypoint};
    use super::*;
    use keylo_core::DescriptorData;

    fn row(d: &Descriptors, i: usize) -> &[u8] {
        match &d.data {
            DescriptorData::Binary(b) => &b[i * d.dim..(i + 1) * d.dim],
            DescriptorData::Float(_) => panic!("float descriptors"),
        }
    }

    /// keylo's own FREAK (`pattern = "trained"`); OpenCV's is held to OpenCV's output in
    /// `tests/brief_freak_opencv.rs`.
    fn describe(params: &FreakParams, img: &Image, kps: &mut Vec<Keypoint>) -> Descriptors {
        let params = FreakParams {
            pattern: FreakPattern::Trained,
            ..params.clone()
        };
        Freak::new(&params).unwrap().compute(img, kps).unwrap()
    }

    #[test]
    fn orientation_makes_it_rotation_invariant() {
        let (cx, cy) = (40.0, 40.0);
        let up = blobs(80, 80, cx, cy, 0.0);
        let on = FreakParams::default();
        let off = FreakParams {
            orientation_normalized: false,
            ..FreakParams::default()
        };
        for deg in [15.0f32, 40.0, 90.0, 200.0] {
            let turned = blobs(80, 80, cx, cy, deg);
            let (mut a, mut b) = (vec![keypoint(cx, cy)], vec![keypoint(cx, cy)]);
            let (da, db) = (describe(&on, &up, &mut a), describe(&on, &turned, &mut b));
            let turn = (b[0].angle - a[0].angle).rem_euclid(360.0);
            let err = (turn - deg).abs().min(360.0 - (turn - deg).abs());
            assert!(err < 5.0, "{deg}°: estimated turn {turn}°");
            let invariant = hamming(row(&da, 0), row(&db, 0));
            let (mut c, mut d) = (vec![keypoint(cx, cy)], vec![keypoint(cx, cy)]);
            let (dc, dd) = (describe(&off, &up, &mut c), describe(&off, &turned, &mut d));
            let plain = hamming(row(&dc, 0), row(&dd, 0));
            assert!(
                invariant < 60 && invariant * 3 < plain,
                "{deg}°: {invariant} vs {plain}"
            );
        }
    }

    #[test]
    fn drops_keypoints_whose_pattern_leaves_the_image() {
        let img = blobs(100, 64, 50.0, 32.0, 0.0);
        // At scale 1 the pattern reaches 22 px, with the margin 23: 23 < y < 64 - 23.
        let mut kps = vec![
            keypoint(50.0, 23.0),
            keypoint(50.0, 24.0),
            keypoint(50.0, 40.0),
            keypoint(50.0, 41.0),
            keypoint(23.0, 32.0),
            Keypoint {
                size: 14.0,
                ..keypoint(50.0, 32.0)
            },
        ];
        let d = describe(&FreakParams::default(), &img, &mut kps);
        let ys: Vec<f32> = kps.iter().map(|k| k.y).collect();
        assert_eq!(ys, vec![24.0, 40.0]);
        assert_eq!((d.rows, d.dim), (2, 64));
        // Without scale normalisation the size-14 keypoint fits.
        let mut big = vec![Keypoint {
            size: 14.0,
            ..keypoint(50.0, 32.0)
        }];
        let fixed = FreakParams {
            scale_normalized: false,
            ..FreakParams::default()
        };
        assert_eq!(describe(&fixed, &img, &mut big).rows, 1);
    }

    #[test]
    fn deterministic_self_distance_zero() {
        let img = blobs(100, 64, 50.0, 32.0, 0.0);
        let p = FreakParams::default();
        let mut kps = vec![
            keypoint(45.0, 32.0),
            keypoint(45.0, 32.0),
            keypoint(60.0, 30.0),
        ];
        let d = describe(&p, &img, &mut kps);
        assert_eq!(d, describe(&p, &img, &mut kps.clone()));
        assert_eq!(hamming(row(&d, 0), row(&d, 1)), 0);
        assert!(hamming(row(&d, 0), row(&d, 2)) > 64);
        assert!(kps.iter().all(|k| (0.0..360.0).contains(&k.angle)));
    }

    #[test]
    fn bad_parameters_and_two_plane_images_are_errors() {
        let e = Freak::new(&FreakParams {
            pattern_scale: -1.0,
            ..FreakParams::default()
        })
        .err()
        .unwrap();
        assert!(e.to_string().contains("`pattern_scale`"), "{e}");
        let e = Freak::new(&FreakParams {
            pattern_scale: 1e10,
            ..FreakParams::default()
        })
        .err()
        .unwrap();
        assert!(e.to_string().contains("`pattern_scale`"), "{e}");
        let e = Freak::new(&FreakParams {
            n_octaves: 0,
            ..FreakParams::default()
        })
        .err()
        .unwrap();
        assert!(e.to_string().contains("`n_octaves`"), "{e}");
        let mut img = blobs(60, 60, 30.0, 30.0, 0.0);
        img.channels = 2;
        img.stride = 120;
        img.data = vec![0; 120 * 60];
        let mut f = Freak::new(&FreakParams::default()).unwrap();
        let e = f
            .compute(&img, &mut vec![keypoint(30.0, 30.0)])
            .unwrap_err();
        assert!(e.to_string().contains("one-plane"), "{e}");
    }
}
