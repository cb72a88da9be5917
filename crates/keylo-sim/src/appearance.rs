//! How the simulated images look beyond the ideal physics: `ideal` (the shading model alone)
//! or `ouster`, the effects measured on real OS0-128 signal images (the TIERS images of the
//! paper's keypoint study; `keylo sim realism`, docs/results/sim-realism.md):
//!
//! * signal level: the real images are Ouster's ROS driver's (auto exposure, then a square
//!   root; `[image.normalise] method = "ouster-ros"`), whose grey steps in dark regions
//!   (17, 24, 29, 34 … = 17 · √k) put the 90th percentile of the counts near 200;
//! * per-beam gain: rows repeat a pattern of four gains that deepens in the middle rows
//!   (one beam of four down to 0.75–0.85 of its neighbours in grey), measured per beam;
//! * per-beam range response: each beam's gain also wanders with range, differently for
//!   every beam, so a surface shows row-to-row streaks the fixed gains do not explain;
//! * noise: a still sensor's counts vary as photon shot noise (Poisson);
//! * near field: below ~4 m the signal falls short of `1/r²` (the real images are brightest
//!   on the walls, not on the floor next to the sensor);
//! * incidence: grazing surfaces are darker than Lambert's law says (cos² of the angle);
//! * every return the sensor reports has at least one count (the real images have almost
//!   no black pixels);
//! * dropouts: weak returns (dark, far or grazing surfaces) are lost at random;
//! * partial drops: a pixel now and then reads a fraction of its signal, in short runs;
//! * mixed pixels: a pixel beside a range jump along its row reads part of its signal (its
//!   beam falls partly on the other surface; measured on the real Ouster captures).
//!
//! The scenes add what a real hall holds (the lab: painted walls, a plain floor, clutter);
//! with `ideal` every scene is the one it always was, frame for frame.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::mixed_pixels::MixedPixels;
use crate::noise::{hash_words, unit};
use crate::partial_drops::PartialDrops;

/// Which image effects the simulator adds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Appearance {
    /// The shading model alone (the default until 2026-12-05; parity tests and fixtures ask
    /// for it by name).
    Ideal,
    /// With the signal level and beam gains of a real Ouster OS0-128: the default, as every
    /// simulated sensor is an Ouster.
    #[default]
    Ouster,
}

/// Real signal counts over the ideal model's. The TIERS images' dark regions take the grey
/// levels 17, 24, 29, 34, 38, 41 … of `17 · √k`: under the driver's exposure (`0.9 · counts
/// / hi` when the 10th percentile is low, then the square root) one count reads grey 17 when
/// `hi`, the 90th percentile of the frame's non-zero counts, is about 200. The still lab's
/// frames with this scale: `hi` 208 (median over 24 layouts).
const SIGNAL_SCALE: f64 = 0.38;

/// The gain table below is measured on the driver's square-root images, as grey ratios; in
/// counts each gain is its 1.5th power. Measured as the table was (`beam_gains.py`: per row,
/// the median pixel over the mean of the rows ±1, ±2), the still lab then shows a spread
/// over rows of 0.094 (per eighth of the rows, top first: 0.027 0.034 0.081 0.121 0.104
/// 0.137 0.127 0.050) against the real 0.089 (0.027 0.030 0.076 0.115 0.100 0.128 0.124
/// 0.047); with the square, the plain inverse of the square root, 0.123; with the table as
/// it is, 0.063 (without the range response, which adds its own spread).
const BEAM_GAIN_POWER: f64 = 1.5;

/// Grey-level gain of each beam of the real OS0-128 (normalised to mean 1): a pattern of four
/// that deepens in the middle rows. Made by `scripts/sim/beam_gains.py` from the 200 TIERS
/// images (`/usr/bin/python3 scripts/sim/beam_gains.py ../shared/data/tiers_signal`).
#[rustfmt::skip]
const OS0_128_BEAM_GAINS: [f64; 128] = [
    1.072, 1.053, 1.013, 1.009, 1.020, 1.023, 0.985, 0.996,
    1.066, 1.013, 0.984, 0.971, 1.050, 0.999, 0.996, 0.975,
    1.042, 1.031, 0.965, 1.000, 1.029, 1.019, 0.984, 0.964,
    1.072, 1.004, 0.991, 0.979, 1.025, 1.050, 0.996, 0.977,
    1.078, 1.029, 1.004, 0.951, 1.080, 1.038, 0.988, 0.891,
    1.083, 1.089, 0.993, 0.838, 1.101, 1.090, 0.968, 0.810,
    1.125, 1.098, 0.966, 0.835, 1.149, 1.074, 0.973, 0.834,
    1.103, 1.085, 0.954, 0.860, 1.100, 1.054, 0.983, 0.860,
    1.097, 1.079, 0.992, 0.840, 1.089, 1.110, 0.973, 0.836,
    1.081, 1.080, 1.013, 0.836, 1.041, 1.028, 0.973, 0.840,
    1.088, 1.027, 1.001, 0.816, 1.078, 1.100, 0.948, 0.756,
    1.126, 1.179, 0.939, 0.768, 1.150, 1.191, 0.951, 0.740,
    1.066, 1.118, 1.055, 0.776, 1.000, 1.086, 1.050, 0.867,
    0.992, 1.005, 1.054, 0.935, 1.019, 0.989, 1.036, 0.926,
    0.971, 1.053, 1.033, 0.948, 0.962, 1.043, 1.028, 0.956,
    0.924, 1.058, 1.047, 0.984, 0.980, 0.984, 0.991, 0.867,
];

/// How far each beam's gain wanders with range: up to `± RANGE_WANDER` of it, smoothly, over
/// steps of `RANGE_WANDER_STEP_M`, fading with range. Measured two ways:
/// * the TIERS images' row-to-row residual (a pixel minus the mean of the pixels above and
///   below; `scripts/sim/row_residual.py`): median over the image 13.5 grey levels, the lab's
///   8.9 without the wandering and 12.3 with it (column residual 6.5 in all three);
/// * in the OS0-128 capture of `../shared/data/ouster` (range and signal), the spread over
///   beams of each beam's gain relative to its neighbours, per range bin
///   (`scripts/sim/beam_range_response.py`): 0.21 below 1.5 m, 0.18 at 2–3 m, 0.13 at
///   3–4 m; in the lab 0.07 and 0.04 at 2–4 m without the wandering, 0.11 and 0.06 with it
///   (still below the real sensor's).
const RANGE_WANDER: f64 = 0.35;

/// Range over which a beam's gain changes independently, metres.
const RANGE_WANDER_STEP_M: f64 = 1.0;

/// Range at which the wandering has faded to half: the spread over beams in the OS0-128
/// capture falls from 0.21 below 1.5 m to 0.13 at 3–4 m.
const RANGE_WANDER_FADE_M: f64 = 5.0;

/// Range below which the real signal falls short of `1/r²`, metres: with the driver's square
/// root, the real images' row profile (mean grey per eighth of the rows, top first: 128 151
/// 161 151 136 109 69 58) wants a dark floor next to the sensor; the still lab with 4 m:
/// 136 158 172 176 156 94 60 69.
const NEAR_FIELD_M: f64 = 4.0;

/// Variance of the real signal over its mean: photon shot noise alone. Under the driver's
/// square root such noise reads about the same number of grey levels whatever the signal
/// (8.5 when one count is grey 17): the still TIERS images differ from their median by a
/// robust σ of 7.41 grey levels, and the still lab by 7.41 with this factor (5.93 with 0.76,
/// 8.15 with 1.2; `scripts/sim/noise_correlation.py`, 24 frames each).
const NOISE_FACTOR: f64 = 1.0;

/// Extra power of the cosine of incidence: the signal falls as cos² of the angle of
/// incidence rather than Lambert's cos. With the driver's square root and Lambert's law
/// alone the still lab's grazing floor and ceiling read too bright: grey percentiles 10 / 25
/// / 50 of 53 / 76 / 136 against the real 29 / 56 / 115, mean grey per eighth of the rows
/// 156 173 180 182 162 108 78 82 against 128 151 161 151 136 109 69 58; with cos²: 35 / 60 /
/// 119 and 136 158 172 176 156 94 60 69.
const GRAZING_POWER: f64 = 1.0;

/// Fewest counts of a return the sensor reports.
const MIN_RETURN_COUNTS: f64 = 1.0;

/// Model signal (counts of the ideal model) at which a return is lost one time in two: weak
/// returns of dark and glossy surfaces break up. Kept low: the real images have almost no
/// black pixels (0.13 % are 0; the still lab: 0.45 %), so most of the weak real returns are
/// dim, not lost: their one to four counts read grey 17–34.
const DROPOUT_COUNTS: f64 = 4.0;

/// Partial drops, as the TIERS images show them (`scripts/sim/partial_drops.py`: 40 still
/// images, each pixel against its median over them). Pixels below half their median grey,
/// by median grey level g: 1.01 % at 40–80, 0.92 % at 80–120, 0.20 % at 120–160, 0.14 %
/// above (the still lab with these constants: 1.86, 0.69, 0.08, 0.01 %: its shot noise
/// alone drops dim pixels that far now and then); more on the near floor (the last eighth
/// of the rows: 4.7 %; not modelled). Runs along a row: 78 % one pixel long, 15 % two, 4 %
/// three (the lab: 85, 10, 2 %). A dropped pixel reads 0.14 / 0.28 / 0.38 of its median grey
/// (10th / 50th / 90th percentile; the lab 0.16 / 0.33 / 0.46), so 0.02 / 0.08 / 0.14 of
/// its counts under the driver's square root: `low`–`high` are counts. Grey 100 is 34 counts when one count is grey 17.
/// The OS0-128 capture of `../shared/data/ouster` (firmware 3.0.1, 1024 columns) shows none:
/// 0 of 22 911 pixel pairs of its two consecutive frames differ by a factor of two.
const PARTIAL_DROPS: PartialDrops = PartialDrops {
    rate: 0.01,
    reference: 34.0,
    exponent: 4.5,
    max_rate: 0.01,
    continue_prob: 0.25,
    low: 0.01,
    high: 0.25,
};

/// Mixed pixels, as the real Ouster captures show them (`scripts/sim/mixed_pixels.py`): a
/// pixel beside a range jump along its row (more than 0.3 · r + 0.2 m to its left or right
/// neighbour) reads 0.59–0.77 of the signal of the same surface two pixels further in
/// (median; quartiles 0.27–0.51 and 0.91–1.00), against 0.99 inside a surface (OS0-128 and
/// OS-2-128 captures of `../shared/data/ouster`, 1024 columns). The lab without them:
/// 0.96–1.00.
const MIXED_PIXELS: MixedPixels = MixedPixels {
    relative: 0.3,
    absolute_m: 0.2,
    low: 0.3,
    high: 1.0,
};

impl Appearance {
    /// Returns beside a range jump dimmed (`None` for `ideal`).
    pub fn mixed_pixels(self) -> Option<MixedPixels> {
        match self {
            Self::Ideal => None,
            Self::Ouster => Some(MIXED_PIXELS),
        }
    }

    /// Model signal at which returns drop out one time in two (0: never).
    pub fn dropout_counts(self) -> f64 {
        match self {
            Self::Ideal => 0.0,
            Self::Ouster => DROPOUT_COUNTS,
        }
    }

    /// Returns measured far too low at random (`None` for `ideal`).
    pub fn partial_drops(self) -> Option<PartialDrops> {
        match self {
            Self::Ideal => None,
            Self::Ouster => Some(PARTIAL_DROPS),
        }
    }

    /// Extra power of the cosine of incidence in the signal (0 for `ideal`: Lambert's law).
    pub fn grazing_power(self) -> f64 {
        match self {
            Self::Ideal => 0.0,
            Self::Ouster => GRAZING_POWER,
        }
    }

    /// Fewest counts of a reported return (0 for `ideal`: its shot noise may read 0).
    pub fn min_return_counts(self) -> f64 {
        match self {
            Self::Ideal => 0.0,
            Self::Ouster => MIN_RETURN_COUNTS,
        }
    }

    /// Variance of the signal over its mean (1: shot noise alone).
    pub fn noise_factor(self) -> f64 {
        match self {
            Self::Ideal => 1.0,
            Self::Ouster => NOISE_FACTOR,
        }
    }

    /// Whether the sensor has a real sensor's staggered beams (`ouster`, on an OS0-128;
    /// [`crate::sensor::SensorModel::staggered`]).
    pub fn staggered_beams(self) -> bool {
        match self {
            Self::Ideal => false,
            Self::Ouster => true,
        }
    }

    /// The near-field range of the signal model (0: none).
    pub fn near_field_m(self) -> f64 {
        match self {
            Self::Ideal => 0.0,
            Self::Ouster => NEAR_FIELD_M,
        }
    }

    /// The signal response of every beam (row) of a `rows`-beam sensor (gain 1 for
    /// `ideal`; for `ouster`, the measured OS0-128 gains, sampled at the same place in the
    /// four-beam pattern for other beam counts, each wandering with range).
    pub fn beam_responses(self, rows: usize) -> Vec<BeamResponse> {
        match self {
            Self::Ideal => vec![BeamResponse::UNIT; rows],
            Self::Ouster => (0..rows)
                .map(|r| {
                    let block = (r / 4) * 128 / rows.max(1);
                    let i = (4 * block + r % 4).min(127);
                    BeamResponse {
                        gain: SIGNAL_SCALE * OS0_128_BEAM_GAINS[i].powf(BEAM_GAIN_POWER),
                        wander: RANGE_WANDER,
                        seed: hash_words(&[0xBEA4_4E5F, i as u64]),
                    }
                })
                .collect(),
        }
    }
}

/// The signal gain of one beam: a fixed gain that wanders smoothly with range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamResponse {
    /// Gain over the ideal model's signal.
    gain: f64,
    /// How far the gain wanders with range (share of it; 0: not at all).
    wander: f64,
    /// The beam's own wandering (a property of the sensor, the same in every scene).
    seed: u64,
}

impl BeamResponse {
    /// The ideal beam: gain 1 at every range.
    pub const UNIT: Self = Self {
        gain: 1.0,
        wander: 0.0,
        seed: 0,
    };

    /// The gain at `range_m` metres.
    pub fn at(&self, range_m: f64) -> f64 {
        if self.wander == 0.0 {
            return self.gain;
        }
        let x = range_m.max(0.0) / RANGE_WANDER_STEP_M;
        let (i, f) = (x.floor(), x.fract());
        let knot = |k: f64| 2.0 * f64::from(unit(hash_words(&[self.seed, k as u64]))) - 1.0;
        let s = f * f * (3.0 - 2.0 * f);
        let (k0, k1) = (knot(i), knot(i + 1.0));
        let n = k0 + (k1 - k0) * s;
        let fade = 1.0 / (1.0 + (range_m / RANGE_WANDER_FADE_M).powi(2));
        self.gain * (1.0 + self.wander * fade * n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gains of a sensor's beams at `range_m`.
    fn gains(look: Appearance, rows: usize, range_m: f64) -> Vec<f64> {
        let beams = look.beam_responses(rows);
        beams.iter().map(|b| b.at(range_m)).collect()
    }

    #[test]
    fn ideal_has_unit_gains_ouster_the_measured_pattern() {
        assert_eq!(gains(Appearance::Ideal, 3, 7.3), vec![1.0; 3]);
        // On the range steps the wandering is at its knots; its mean over beams is near 0.
        let g: Vec<f64> = (0..128)
            .map(|r| {
                (0..40)
                    .map(|k| gains(Appearance::Ouster, 128, 0.25 * k as f64 + 0.1)[r])
                    .sum::<f64>()
                    / 40.0
            })
            .collect();
        let mean = g.iter().sum::<f64>() / 128.0;
        assert!((mean / SIGNAL_SCALE - 1.0).abs() < 0.03, "{mean}");
        // The weak beam of each four in the middle rows, averaged over the mid rows.
        let phase = |p: usize| (40..100).filter(|r| r % 4 == p).map(|r| g[r]).sum::<f64>();
        assert!(phase(3) < 0.9 * phase(0), "{g:?}");
        // Other beam counts sample the same beams (gain and wandering).
        let (g128, g64) = (
            gains(Appearance::Ouster, 128, 4.4),
            gains(Appearance::Ouster, 64, 4.4),
        );
        assert_eq!(g64.len(), 64);
        assert_eq!(g64[3], g128[3]);
        assert_eq!(g64[63], g128[123]);
    }

    #[test]
    fn a_beam_wanders_smoothly_and_within_bounds() {
        let beam = Appearance::Ouster.beam_responses(128)[10];
        let base = SIGNAL_SCALE * OS0_128_BEAM_GAINS[10];
        let g: Vec<f64> = (0..2000).map(|k| beam.at(k as f64 * 0.01) / base).collect();
        assert!(g
            .iter()
            .all(|x| (1.0 - RANGE_WANDER..=1.0 + RANGE_WANDER).contains(x)));
        // Smooth: 1 cm apart differs by far less than the whole swing.
        let step = g
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        assert!(step < 0.02, "{step}");
        let (lo, hi) = g
            .iter()
            .fold((9.0f64, 0.0f64), |(l, h), x| (l.min(*x), h.max(*x)));
        assert!(hi - lo > 0.2, "{lo}..{hi}");
        // Beams wander differently.
        let other = Appearance::Ouster.beam_responses(128)[11];
        let ratio = |r: f64| beam.at(r) / other.at(r);
        assert!((ratio(2.0) - ratio(5.0)).abs() > 1e-3);
    }
}
