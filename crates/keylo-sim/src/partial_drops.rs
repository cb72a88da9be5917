//! Partial drops: returns whose signal reads far below its mean, at random, in short runs
//! along a row (the `ouster` appearance; measured on the TIERS images).

use crate::noise::{hash_words, unit, PixelRng};

/// Returns whose signal is measured far below its mean, at random: in still real images a
/// pixel now and then reads a fraction of its usual signal, more often the dimmer it is,
/// in short runs along the row. A pixel of mean signal `s` counts starts such a run with
/// probability `min(max_rate, rate · (reference / s)^exponent)`; the run goes on to the next
/// column with probability `continue_prob`; each pixel of it reads `low..high` of its signal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartialDrops {
    /// Start rate at `reference` counts.
    pub rate: f64,
    /// Signal (counts) at which the start rate is `rate`.
    pub reference: f64,
    /// How fast the rate falls with the signal.
    pub exponent: f64,
    /// Largest start rate (dim pixels).
    pub max_rate: f64,
    /// Probability that a run covers the next column too.
    pub continue_prob: f64,
    /// Range of the share of its signal a dropped pixel reads.
    pub low: f64,
    /// See `low`.
    pub high: f64,
}

/// Salt of the partial-drop events' hashes.
const PARTIAL_DROP_SALT: u64 = 0xD20B_5EED;

/// Longest run of partial drops followed back along the row, columns.
const PARTIAL_DROP_MAX_RUN: u64 = 6;

impl PartialDrops {
    /// The share of its signal the pixel of `rng` reads (1: not dropped), for mean signal
    /// `mean` (counts). A run that started up to [`PARTIAL_DROP_MAX_RUN`] columns to the left
    /// covers this pixel when each column in between continued it; runs are judged by this
    /// pixel's own signal (neighbours along a row are alike).
    pub fn factor(&self, mean: f64, rng: &mut PixelRng) -> f64 {
        let start =
            (self.rate * (self.reference / mean.max(1.0)).powf(self.exponent)).min(self.max_rate);
        // Rate of run starts such that a pixel is covered `start` of the time on average.
        let start = start * (1.0 - self.continue_prob);
        for back in 0..PARTIAL_DROP_MAX_RUN {
            let h = rng.along_row(back, PARTIAL_DROP_SALT);
            if f64::from(unit(h)) >= start {
                continue;
            }
            // The run's length beyond its first column: geometric.
            let covered =
                (1..=back).all(|k| f64::from(unit(hash_words(&[h, k]))) < self.continue_prob);
            if covered {
                return self.low + (self.high - self.low) * rng.uniform();
            }
        }
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DROPS: PartialDrops = PartialDrops {
        rate: 0.01,
        reference: 20_000.0,
        exponent: 3.0,
        max_rate: 0.05,
        continue_prob: 0.25,
        low: 0.1,
        high: 0.5,
    };

    /// Factors of one row of `cols` pixels of mean signal `mean`.
    fn row(mean: f64, row: usize, cols: usize) -> Vec<f64> {
        (0..cols)
            .map(|c| DROPS.factor(mean, &mut PixelRng::for_pixel(7, 3, row, c)))
            .collect()
    }

    #[test]
    fn dim_pixels_drop_more_often_in_short_runs_to_a_fraction_of_their_signal() {
        let cols = 200_000;
        let rate = |f: &[f64]| f.iter().filter(|&&x| x < 1.0).count() as f64 / f.len() as f64;
        let at_ref = row(20_000.0, 0, cols);
        let bright = row(40_000.0, 1, cols);
        let dim = row(2_000.0, 2, cols);
        // Covered `rate` of the time at the reference, 2³ times less at twice the signal,
        // at most `max_rate` when dim.
        assert!((rate(&at_ref) - 0.01).abs() < 0.002, "{}", rate(&at_ref));
        assert!(
            (rate(&bright) - 0.00125).abs() < 0.0005,
            "{}",
            rate(&bright)
        );
        assert!((rate(&dim) - 0.05).abs() < 0.005, "{}", rate(&dim));
        assert!(dim.iter().all(|&x| x == 1.0 || (0.1..0.5).contains(&x)));
        // Runs along the row: a dropped pixel's right neighbour is dropped about
        // `continue_prob` of the time, far more than the rate alone gives.
        let dropped: Vec<bool> = dim.iter().map(|&x| x < 1.0).collect();
        let pairs = dropped.windows(2).filter(|w| w[0] && w[1]).count() as f64;
        let follow = pairs / dropped.iter().filter(|&&d| d).count() as f64;
        assert!((0.18..0.32).contains(&follow), "{follow}");
    }

    #[test]
    fn the_same_pixel_drops_the_same_way() {
        assert_eq!(row(2_000.0, 5, 1000), row(2_000.0, 5, 1000));
        assert_ne!(row(2_000.0, 5, 1000), row(2_000.0, 6, 1000));
    }
}
