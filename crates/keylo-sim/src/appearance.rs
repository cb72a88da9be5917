//! How the simulated images look beyond the ideal physics: `ideal` (the shading model alone)
//! or `ouster`, the effects measured on real OS0-128 signal images (the TIERS images of the
//! paper's keypoint study; `keylo sim realism`, docs/results/sim-realism.md):
//!
//! * signal level: real indoor returns are tens of thousands of counts (median grey level 115
//!   of the 8-bit images made as `counts / 256`), `SIGNAL_SCALE` times the ideal model's;
//! * per-beam gain: rows repeat a pattern of four gains that deepens in the middle rows
//!   (one beam of four down to 0.75–0.85 of its neighbours), measured per beam;
//! * noise: a still sensor's images differ by ~√200 times the photon shot noise;
//! * near field: below ~3 m the signal falls short of `1/r²` (the real images are brightest
//!   on the walls, not on the floor next to the sensor);
//! * dropouts: weak returns (dark, far or grazing surfaces) are lost at random.
//!
//! The scenes add what a real hall holds (the lab: painted walls, a plain floor, clutter);
//! with `ideal` every scene is the one it always was, frame for frame.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Which image effects the simulator adds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Appearance {
    /// The shading model alone.
    #[default]
    Ideal,
    /// With the signal level and beam gains of a real Ouster OS0-128.
    Ouster,
}

/// Real signal counts over the ideal model's.
const SIGNAL_SCALE: f64 = 84.0;

/// Signal gain of each beam of the real OS0-128 (normalised to mean 1): a pattern of four
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

/// Range below which the real signal falls short of `1/r²`, metres.
const NEAR_FIELD_M: f64 = 3.0;

/// Variance of the real signal over its mean: consecutive images of a still sensor differ by
/// σ ≈ 10 grey levels (2 600 counts) at 30 000 counts and ≈ 5 at 10 000 (57 still pairs of the
/// TIERS images), about √200 times the photon shot noise.
const NOISE_FACTOR: f64 = 200.0;

/// Model signal (counts of the ideal model) at which a return is lost one time in two: weak
/// returns of dark and glossy surfaces break up. Kept low: the real images have almost no
/// empty pixels (0.1 % are 0), so most of the weak real returns are dim, not lost.
const DROPOUT_COUNTS: f64 = 15.0;

impl Appearance {
    /// Model signal at which returns drop out one time in two (0: never).
    pub fn dropout_counts(self) -> f64 {
        match self {
            Self::Ideal => 0.0,
            Self::Ouster => DROPOUT_COUNTS,
        }
    }

    /// Variance of the signal over its mean (1: shot noise alone).
    pub fn noise_factor(self) -> f64 {
        match self {
            Self::Ideal => 1.0,
            Self::Ouster => NOISE_FACTOR,
        }
    }

    /// The near-field range of the signal model (0: none).
    pub fn near_field_m(self) -> f64 {
        match self {
            Self::Ideal => 0.0,
            Self::Ouster => NEAR_FIELD_M,
        }
    }

    /// The signal gain of every beam (row) of a `rows`-beam sensor (1 for `ideal`; for
    /// `ouster`, the measured OS0-128 gains, sampled at the same place in the four-beam
    /// pattern for other beam counts).
    pub fn beam_gains(self, rows: usize) -> Vec<f64> {
        match self {
            Self::Ideal => vec![1.0; rows],
            Self::Ouster => (0..rows)
                .map(|r| {
                    let block = (r / 4) * 128 / rows.max(1);
                    let i = (4 * block + r % 4).min(127);
                    SIGNAL_SCALE * OS0_128_BEAM_GAINS[i]
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ideal_has_unit_gains_ouster_the_measured_pattern() {
        assert_eq!(Appearance::Ideal.beam_gains(3), vec![1.0; 3]);
        let g = Appearance::Ouster.beam_gains(128);
        let mean = g.iter().sum::<f64>() / 128.0;
        assert!((mean / SIGNAL_SCALE - 1.0).abs() < 1e-3, "{mean}");
        // The weak beam of each four in the middle rows.
        assert!(g[47] < 0.9 * g[44], "{g:?}");
        let g64 = Appearance::Ouster.beam_gains(64);
        assert_eq!(g64.len(), 64);
        assert_eq!(g64[3], g[3]);
        assert_eq!(g64[63], g[123]);
    }
}
