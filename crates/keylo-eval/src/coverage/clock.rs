//! Plain facts about a list of stamps: its range and typical step.

use serde::Serialize;

/// First and last stamp (smallest and largest finite one), seconds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TimeRange {
    /// Smallest stamp.
    pub first: f64,
    /// Largest stamp.
    pub last: f64,
}

impl TimeRange {
    /// The range of the finite `stamps`; `None` when there is none.
    pub fn of(stamps: &[f64]) -> Option<Self> {
        let mut finite = stamps.iter().copied().filter(|t| t.is_finite());
        let first = finite.next()?;
        let (first, last) = finite.fold((first, first), |(a, b), t| (a.min(t), b.max(t)));
        Some(Self { first, last })
    }

    /// `last - first`.
    pub fn span(&self) -> f64 {
        self.last - self.first
    }

    /// Length of the time both ranges cover (0 when they are apart).
    pub fn overlap(&self, other: &Self) -> f64 {
        (self.last.min(other.last) - self.first.max(other.first)).max(0.0)
    }
}

impl std::fmt::Display for TimeRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} … {}", seconds(self.first), seconds(self.last))
    }
}

/// A stamp in seconds for messages: 3 decimals, or 7 significant digits when huge (ns).
pub fn seconds(t: f64) -> String {
    if t.abs() >= 1e12 {
        format!("{t:.6e}")
    } else {
        format!("{t:.3}")
    }
}

/// The median of the positive differences between consecutive sorted stamps.
pub fn median_step(stamps: &[f64]) -> Option<f64> {
    let mut sorted: Vec<f64> = stamps.iter().copied().filter(|t| t.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let steps: Vec<f64> = sorted
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    median(steps)
}

/// The median of `values` (the lower middle one for an even count).
pub fn median(mut values: Vec<f64>) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    values.get(values.len().checked_sub(1)? / 2).copied()
}

/// `x` rounded to `digits` significant digits (0 stays 0).
pub fn round_significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let magnitude = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * magnitude).round() / magnitude
}

/// The number with the fewest significant digits (up to 9) within `1e-5` of `x`, relative:
/// a step read from stamps with rounding noise (0.0999999 on the Unix epoch) as 0.1.
pub fn simplest(x: f64) -> f64 {
    (1..=9)
        .map(|d| round_significant(x, d))
        .find(|r| (r - x).abs() <= 1e-5 * x.abs())
        .unwrap_or(x)
}

/// `x` rounded to microseconds, with `|x| <= tolerance` taken as 0.
pub fn round_offset(x: f64, tolerance: f64) -> f64 {
    if x.abs() <= tolerance {
        0.0
    } else {
        (x * 1e6).round() / 1e6
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_step_and_rounding() {
        let r = TimeRange::of(&[3.0, f64::NAN, 1.0, 2.0]).unwrap();
        assert_eq!((r.first, r.last, r.span()), (1.0, 3.0, 2.0));
        assert_eq!(
            r.overlap(&TimeRange {
                first: 2.5,
                last: 9.0
            }),
            0.5
        );
        assert_eq!(
            r.overlap(&TimeRange {
                first: 5.0,
                last: 9.0
            }),
            0.0
        );
        assert_eq!(median_step(&[0.0, 0.1, 0.2, 0.2, 0.5]), Some(0.1));
        assert_eq!(median_step(&[1.0]), None);
        assert_eq!(round_significant(0.099_999_999_7, 6), 0.1);
        assert_eq!(simplest(0.099_999_904_6), 0.1);
        assert_eq!(simplest(0.100_05), 0.100_05);
        assert_eq!(round_offset(0.004, 0.01), 0.0);
        assert_eq!(seconds(1.6e18), "1.600000e18");
    }
}
