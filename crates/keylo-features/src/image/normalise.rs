//! A frame channel (f32 per pixel) to 8 bits: fixed scale, percentile clip or histogram
//! equalisation, then an optional gamma; or as Ouster's ROS driver does. Invalid pixels
//! become 0.

use serde::{Deserialize, Serialize};

use crate::{check, FeaturesError};

/// How channel values map to 0–255.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum NormaliseMethod {
    /// `value * scale + offset`, clipped to 0–255.
    Fixed,
    /// The `low_percentile`–`high_percentile` range of the frame's valid pixels stretched
    /// linearly to 0–255 (values outside clip).
    #[default]
    Percentile,
    /// Histogram equalisation over the frame's valid pixels (each value becomes its rank,
    /// in 256 levels).
    Equalise,
    /// As Ouster's ROS driver makes its signal images (the images of the paper): the frame's
    /// 10th and 90th percentiles of non-zero values to 0.1 and 0.9, clipped, square root, top
    /// byte of the 16-bit result. The other fields are not used.
    OusterRos,
}

/// How one channel becomes an 8-bit image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct Normalise {
    /// `fixed`, `percentile`, `equalise` or `ouster-ros`.
    pub method: NormaliseMethod,
    /// `fixed`: multiplier applied to the channel value (range in metres, signal in counts).
    pub scale: f64,
    /// `fixed`: added after scaling.
    pub offset: f64,
    /// `percentile`: the value mapped to 0, as a percentile (0–100) of valid pixels.
    pub low_percentile: f64,
    /// `percentile`: the value mapped to 255, as a percentile (0–100) of valid pixels.
    pub high_percentile: f64,
    /// Gamma applied to the 0–1 result before quantising (1: none; 0.5 brightens dark
    /// pixels, as the paper's authors did for range images).
    pub gamma: f64,
}

impl Default for Normalise {
    fn default() -> Self {
        Self {
            method: NormaliseMethod::Percentile,
            scale: 1.0,
            offset: 0.0,
            low_percentile: 0.0,
            high_percentile: 99.0,
            gamma: 1.0,
        }
    }
}

impl Normalise {
    /// Checks the parameters; `field` names the config table in messages.
    pub fn validate(&self, field: &str) -> Result<(), FeaturesError> {
        let (lo, hi) = (self.low_percentile, self.high_percentile);
        check(
            (0.0..=100.0).contains(&lo) && (0.0..=100.0).contains(&hi) && lo < hi,
            &format!("{field}.low_percentile/high_percentile"),
            (lo, hi),
            "expected 0 <= low_percentile < high_percentile <= 100",
        )?;
        check(
            self.gamma.is_finite() && self.gamma > 0.0,
            &format!("{field}.gamma"),
            self.gamma,
            "expected a finite value > 0",
        )?;
        check(
            self.scale.is_finite() && self.offset.is_finite(),
            &format!("{field}.scale/offset"),
            (self.scale, self.offset),
            "expected finite values",
        )
    }

    /// The 8-bit image of `values` (row-major, one per pixel); invalid pixels are 0.
    pub fn to_u8(&self, values: &[f32], valid: &[bool]) -> Vec<u8> {
        let mut out = vec![0u8; values.len()];
        let lut_gamma = GammaLut::new(self.gamma);
        match self.method {
            NormaliseMethod::Fixed => {
                let (s, o) = (self.scale as f32, self.offset as f32);
                map_valid(values, valid, &mut out, |v| (v * s + o) / 255.0, &lut_gamma);
            }
            NormaliseMethod::Percentile => {
                let Some((lo, hi)) =
                    percentiles(values, valid, self.low_percentile, self.high_percentile)
                else {
                    return out;
                };
                let span = (hi - lo).max(f32::MIN_POSITIVE);
                map_valid(values, valid, &mut out, |v| (v - lo) / span, &lut_gamma);
            }
            NormaliseMethod::Equalise => equalise(values, valid, &mut out, &lut_gamma),
            NormaliseMethod::OusterRos => super::ouster_ros::driver_image(values, valid, &mut out),
        }
        out
    }
}

/// 0–1 → 0–255 with gamma, through a 4096-entry table.
struct GammaLut {
    table: Option<Vec<u8>>,
}

const GAMMA_STEPS: usize = 4096;

impl GammaLut {
    fn new(gamma: f64) -> Self {
        if gamma == 1.0 {
            return Self { table: None };
        }
        let table = (0..=GAMMA_STEPS)
            .map(|i| ((i as f64 / GAMMA_STEPS as f64).powf(gamma) * 255.0).round() as u8)
            .collect();
        Self { table: Some(table) }
    }

    fn apply(&self, unit: f32) -> u8 {
        let u = if unit.is_finite() {
            unit.clamp(0.0, 1.0)
        } else {
            0.0
        };
        match &self.table {
            None => (u * 255.0).round() as u8,
            Some(t) => t[(u * GAMMA_STEPS as f32).round() as usize],
        }
    }
}

fn map_valid(
    values: &[f32],
    valid: &[bool],
    out: &mut [u8],
    unit: impl Fn(f32) -> f32,
    lut: &GammaLut,
) {
    for ((o, &v), &ok) in out.iter_mut().zip(values).zip(valid) {
        if ok {
            *o = lut.apply(unit(v));
        }
    }
}

/// Most values the percentiles are taken from: larger frames are sampled with an even stride
/// (a 131k-pixel frame: every 4th pixel), which moves a percentile by well under one of the
/// 256 output levels and costs a quarter of the time.
const PERCENTILE_SAMPLES: usize = 32_768;

/// The `lo`-th and `hi`-th percentiles (0–100) of the finite valid values (nearest rank).
fn percentiles(values: &[f32], valid: &[bool], lo: f64, hi: f64) -> Option<(f32, f32)> {
    let stride = values.len().div_ceil(PERCENTILE_SAMPLES).max(1);
    let n = values.len().min(valid.len());
    let mut v: Vec<f32> = (0..n)
        .step_by(stride)
        .filter(|&i| valid[i] && values[i].is_finite())
        .map(|i| values[i])
        .collect();
    if v.is_empty() {
        // Too sparse for the stride: use every valid value.
        v = values
            .iter()
            .zip(valid)
            .filter(|(x, ok)| **ok && x.is_finite())
            .map(|(x, _)| *x)
            .collect();
    }
    if v.is_empty() {
        return None;
    }
    let rank = |p: f64| ((p / 100.0) * (v.len() - 1) as f64).round() as usize;
    let (ilo, ihi) = (rank(lo), rank(hi));
    let (_, &mut hi_v, _) = v.select_nth_unstable_by(ihi, f32::total_cmp);
    // After the partition every value left of `ihi` is <= hi_v: the low rank lies there.
    let (_, &mut lo_v, _) = v[..=ihi].select_nth_unstable_by(ilo, f32::total_cmp);
    Some((lo_v, hi_v))
}

/// Histogram equalisation of the valid values: each becomes its rank fraction in 4096
/// quantisation bins between the minimum and the maximum.
fn equalise(values: &[f32], valid: &[bool], out: &mut [u8], lut: &GammaLut) {
    const BINS: usize = 4096;
    let finite = || {
        values
            .iter()
            .zip(valid)
            .filter(|(x, ok)| **ok && x.is_finite())
            .map(|(x, _)| *x)
    };
    let (min, max) = finite().fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if min > max {
        return;
    }
    let span = (max - min).max(f32::MIN_POSITIVE);
    let bin = |x: f32| (((x - min) / span) * (BINS - 1) as f32).round() as usize;
    let mut hist = vec![0usize; BINS];
    let mut total = 0usize;
    for x in finite() {
        hist[bin(x)] += 1;
        total += 1;
    }
    let mut cdf = vec![0f32; BINS];
    let mut acc = 0usize;
    let first = hist.iter().position(|&h| h > 0).map_or(0, |i| hist[i]);
    let denom = (total - first).max(1) as f32;
    for (c, h) in cdf.iter_mut().zip(&hist) {
        acc += h;
        *c = acc.saturating_sub(first) as f32 / denom;
    }
    for ((o, &v), &ok) in out.iter_mut().zip(values).zip(valid) {
        if ok && v.is_finite() {
            *o = lut.apply(cdf[bin(v)]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentile_stretches_and_zeroes_invalid() {
        let values: Vec<f32> = (0..101).map(|i| i as f32).collect();
        let mut valid = vec![true; 101];
        valid[50] = false;
        let n = Normalise {
            low_percentile: 0.0,
            high_percentile: 100.0,
            ..Normalise::default()
        };
        let img = n.to_u8(&values, &valid);
        assert_eq!(img[0], 0);
        assert_eq!(img[100], 255);
        assert_eq!(img[50], 0);
        assert!(img[25] > 60 && img[25] < 66);
    }

    #[test]
    fn percentile_clips_outliers() {
        let mut values: Vec<f32> = (0..100).map(|i| i as f32).collect();
        values.push(1.0e6);
        let valid = vec![true; values.len()];
        let img = Normalise::default().to_u8(&values, &valid);
        assert_eq!(img[100], 255);
        assert!(
            img[98] > 250,
            "outlier must not squash the rest: {}",
            img[98]
        );
    }

    #[test]
    fn fixed_scale_and_gamma() {
        let n = Normalise {
            method: NormaliseMethod::Fixed,
            scale: 2.0,
            gamma: 0.5,
            ..Normalise::default()
        };
        let img = n.to_u8(&[0.0, 32.0, 200.0], &[true; 3]);
        assert_eq!(img[0], 0);
        // 64/255 = 0.251 -> sqrt = 0.501 -> 128
        assert_eq!(img[1], 128);
        assert_eq!(img[2], 255);
    }

    #[test]
    fn equalise_spreads_ranks() {
        let values = [1.0, 1.0, 2.0, 1000.0];
        let n = Normalise {
            method: NormaliseMethod::Equalise,
            ..Normalise::default()
        };
        let img = n.to_u8(&values, &[true; 4]);
        assert_eq!(img[0], 0);
        assert_eq!(img[3], 255);
        assert!(img[2] > 100 && img[2] < 150, "{}", img[2]);
    }

    #[test]
    fn all_invalid_is_black() {
        let img = Normalise::default().to_u8(&[5.0, 6.0], &[false, false]);
        assert_eq!(img, vec![0, 0]);
    }

    #[test]
    fn bad_percentiles_are_rejected() {
        let n = Normalise {
            low_percentile: 90.0,
            high_percentile: 10.0,
            ..Normalise::default()
        };
        assert!(n.validate("image.normalise").is_err());
    }
}
