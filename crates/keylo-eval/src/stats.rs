//! Error statistics, as evo's `PE.get_all_statistics`.

use crate::EvalError;

/// Summary statistics of an error array.
///
/// Definitions follow evo/numpy: `rmse = sqrt(mean(e²))`, `sse = Σ e²`, `median` averages the
/// two middle values for even `n`, `std` is the population standard deviation (`np.std`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Stats {
    /// Root mean square.
    pub rmse: f64,
    /// Arithmetic mean.
    pub mean: f64,
    /// Median.
    pub median: f64,
    /// Population standard deviation.
    pub std: f64,
    /// Smallest error.
    pub min: f64,
    /// Largest error.
    pub max: f64,
    /// Sum of squared errors.
    pub sse: f64,
    /// Number of errors.
    pub n: usize,
}

impl Stats {
    /// Statistics of `errors`; fails when `errors` is empty.
    ///
    /// ```
    /// let s = keylo_eval::stats::Stats::from_errors(&[1.0, 2.0, 3.0, 4.0])?;
    /// assert_eq!(s.median, 2.5);
    /// assert_eq!(s.sse, 30.0);
    /// assert!((s.std - 1.25f64.sqrt()).abs() < 1e-15);
    /// # Ok::<(), keylo_eval::EvalError>(())
    /// ```
    pub fn from_errors(errors: &[f64]) -> Result<Self, EvalError> {
        if errors.is_empty() {
            return Err(EvalError::InvalidOption {
                name: "errors",
                reason: "statistics of an empty error array".to_string(),
            });
        }
        let n = errors.len() as f64;
        let sse: f64 = errors.iter().map(|e| e * e).sum();
        let mean = errors.iter().sum::<f64>() / n;
        let variance = errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n;
        Ok(Self {
            rmse: (sse / n).sqrt(),
            mean,
            median: median(errors),
            std: variance.sqrt(),
            min: errors.iter().copied().fold(f64::INFINITY, f64::min),
            max: errors.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            sse,
            n: errors.len(),
        })
    }
}

fn median(errors: &[f64]) -> f64 {
    let mut sorted = errors.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mid = sorted.len() / 2;
    if sorted.len() % 2 == 1 {
        sorted[mid]
    } else {
        0.5 * (sorted[mid - 1] + sorted[mid])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_value() {
        let s = Stats::from_errors(&[2.0]).unwrap();
        assert_eq!(
            (s.rmse, s.mean, s.median, s.std, s.min, s.max, s.sse, s.n),
            (2.0, 2.0, 2.0, 0.0, 2.0, 2.0, 4.0, 1)
        );
    }

    #[test]
    fn odd_median_and_empty_error() {
        assert_eq!(Stats::from_errors(&[3.0, 1.0, 2.0]).unwrap().median, 2.0);
        assert!(Stats::from_errors(&[]).is_err());
    }
}
