//! Choosing the pose pairs of RPE, as evo's `filters.filter_pairs_by_index` and
//! `filters.filter_pairs_by_path`.

use keylo_core::Pose;

use crate::EvalError;

/// Pair spacing for RPE (evo `--delta` with `--delta_unit f` or `m`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum Delta {
    /// A number of frames (must be ≥ 1).
    Frames(usize),
    /// A travelled path distance in metres (must be finite and ≥ 0).
    Meters(f64),
}

impl std::fmt::Display for Delta {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Frames(n) => write!(f, "{n} frames"),
            Self::Meters(m) => write!(f, "{m} m"),
        }
    }
}

/// Index pairs `(i, j)` for `delta`; `rel_tol` is evo's `--delta_tol` (all-pairs metres only).
///
/// * frames, consecutive: `(0, δ), (δ, 2δ), …`; all pairs: `(i, i+δ)` for every `i`.
/// * metres, consecutive: walk the path, summing step lengths, and close a pair (then
///   restart the sum at zero) at the first pose where the sum reaches `δ`.
/// * metres, all pairs: for each `i`, the `j > i` whose accumulated distance from `i` is
///   closest to `δ`, kept when within `δ · rel_tol`.
///
/// Fails when the delta is invalid or selects no pair.
///
/// ```
/// use keylo_core::Pose;
/// use keylo_eval::rpe::{pose_pairs, Delta};
/// let poses: Vec<Pose> = (0..7).map(|i| Pose::translation(i as f64, 0.0, 0.0)).collect();
/// assert_eq!(pose_pairs(&poses, Delta::Frames(3), false, 0.1)?, vec![(0, 3), (3, 6)]);
/// assert_eq!(pose_pairs(&poses, Delta::Meters(2.5), false, 0.1)?, vec![(0, 3), (3, 6)]);
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
pub fn pose_pairs(
    poses: &[Pose],
    delta: Delta,
    all_pairs: bool,
    rel_tol: f64,
) -> Result<Vec<(usize, usize)>, EvalError> {
    let pairs = match delta {
        Delta::Frames(0) => return Err(invalid_delta(delta, "must be at least 1 frame")),
        Delta::Meters(m) if !(m.is_finite() && m >= 0.0) => {
            return Err(invalid_delta(
                delta,
                "must be a finite, non-negative distance",
            ))
        }
        Delta::Frames(n) => by_index(poses.len(), n, all_pairs),
        Delta::Meters(m) if all_pairs => by_path_all(poses, m, m * rel_tol),
        Delta::Meters(m) => by_path(poses, m),
    };
    if pairs.is_empty() {
        return Err(EvalError::NoPairs {
            delta: delta.to_string(),
            poses: poses.len(),
        });
    }
    Ok(pairs)
}

fn invalid_delta(delta: Delta, reason: &str) -> EvalError {
    EvalError::InvalidOption {
        name: "delta",
        reason: format!("{delta} {reason}"),
    }
}

fn by_index(n: usize, delta: usize, all_pairs: bool) -> Vec<(usize, usize)> {
    if all_pairs {
        (0..n.saturating_sub(delta))
            .map(|i| (i, i + delta))
            .collect()
    } else {
        let ids: Vec<usize> = (0..n).step_by(delta).collect();
        ids.windows(2).map(|w| (w[0], w[1])).collect()
    }
}

fn step_length(a: &Pose, b: &Pose) -> f64 {
    (b.translation.vector - a.translation.vector).norm()
}

fn by_path(poses: &[Pose], delta: f64) -> Vec<(usize, usize)> {
    let mut ids = vec![0];
    let mut current = 0.0;
    for (i, w) in poses.windows(2).enumerate() {
        current += step_length(&w[0], &w[1]);
        if current >= delta {
            ids.push(i + 1);
            current = 0.0;
        }
    }
    ids.windows(2).map(|w| (w[0], w[1])).collect()
}

/// Accumulated path distance at every pose (`0` at the first).
pub fn accumulated_distances(poses: &[Pose]) -> Vec<f64> {
    let mut out = Vec::with_capacity(poses.len());
    let mut sum = 0.0;
    out.extend(poses.first().map(|_| 0.0));
    for w in poses.windows(2) {
        sum += step_length(&w[0], &w[1]);
        out.push(sum);
    }
    out
}

fn by_path_all(poses: &[Pose], delta: f64, tol: f64) -> Vec<(usize, usize)> {
    let distances = accumulated_distances(poses);
    let mut pairs = Vec::new();
    for i in 0..distances.len().saturating_sub(1) {
        let mut best = (i + 1, f64::INFINITY);
        for (j, d) in distances.iter().enumerate().skip(i + 1) {
            let miss = (d - distances[i] - delta).abs();
            if miss < best.1 {
                best = (j, miss);
            }
        }
        if best.1 <= tol {
            pairs.push((i, best.0));
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize) -> Vec<Pose> {
        (0..n)
            .map(|i| Pose::translation(i as f64, 0.0, 0.0))
            .collect()
    }

    #[test]
    fn frames_consecutive_and_all() {
        assert_eq!(by_index(5, 2, false), vec![(0, 2), (2, 4)]);
        assert_eq!(by_index(5, 2, true), vec![(0, 2), (1, 3), (2, 4)]);
        assert_eq!(by_index(1, 1, false), vec![]);
    }

    #[test]
    fn path_all_pairs_uses_tolerance() {
        let pairs = pose_pairs(&line(5), Delta::Meters(2.0), true, 0.1).unwrap();
        assert_eq!(pairs, vec![(0, 2), (1, 3), (2, 4)]);
    }

    #[test]
    fn invalid_and_empty_deltas() {
        assert!(matches!(
            pose_pairs(&line(3), Delta::Frames(0), false, 0.1),
            Err(EvalError::InvalidOption { .. })
        ));
        assert!(matches!(
            pose_pairs(&line(3), Delta::Meters(f64::NAN), false, 0.1),
            Err(EvalError::InvalidOption { .. })
        ));
        let err = pose_pairs(&line(3), Delta::Meters(10.0), false, 0.1).unwrap_err();
        assert_eq!(
            err.to_string(),
            "delta = 10 m produced an empty list of pose pairs (3 poses); try a lower value"
        );
    }
}
