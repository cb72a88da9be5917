//! Timestamp association, as evo's `sync.associate_trajectories` (nearest-time method).

use keylo_core::Trajectory;

use crate::EvalError;

/// Options of [`associate`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AssociateOptions {
    /// Largest accepted stamp difference, seconds (evo `--t_max_diff`, default 0.01).
    pub max_diff: f64,
    /// Offset added to the estimate's stamps before matching, seconds (evo `--t_offset`).
    pub offset: f64,
}

impl Default for AssociateOptions {
    fn default() -> Self {
        Self {
            max_diff: 0.01,
            offset: 0.0,
        }
    }
}

/// Two trajectories reduced to their matched poses, pose-for-pose paired.
#[derive(Debug, Clone, PartialEq)]
pub struct Associated {
    /// Matched reference poses (reference stamps).
    pub reference: Trajectory,
    /// Matched estimated poses (estimate stamps, without the offset).
    pub estimate: Trajectory,
    /// Index of each pair in the original reference.
    pub reference_indices: Vec<usize>,
    /// Index of each pair in the original estimate.
    pub estimate_indices: Vec<usize>,
}

impl Associated {
    /// Pairs pose `i` with pose `i` (files without stamps, e.g. KITTI); lengths must agree.
    pub fn by_index(reference: &Trajectory, estimate: &Trajectory) -> Result<Self, EvalError> {
        if reference.len() != estimate.len() {
            return Err(EvalError::LengthMismatch {
                reference: "reference".to_string(),
                reference_len: reference.len(),
                estimate: "estimate".to_string(),
                estimate_len: estimate.len(),
            });
        }
        let ids: Vec<usize> = (0..reference.len()).collect();
        Ok(Self::from_indices(reference, estimate, ids.clone(), ids))
    }

    fn from_indices(
        reference: &Trajectory,
        estimate: &Trajectory,
        ref_ids: Vec<usize>,
        est_ids: Vec<usize>,
    ) -> Self {
        Self {
            reference: select(reference, &ref_ids),
            estimate: select(estimate, &est_ids),
            reference_indices: ref_ids,
            estimate_indices: est_ids,
        }
    }

    /// Fails when the (public, hence editable) pose lists differ in length.
    pub fn ensure_paired(&self) -> Result<(), EvalError> {
        if self.reference.len() == self.estimate.len() {
            return Ok(());
        }
        Err(EvalError::LengthMismatch {
            reference: "reference".to_string(),
            reference_len: self.reference.len(),
            estimate: "estimate".to_string(),
            estimate_len: self.estimate.len(),
        })
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.reference.len()
    }

    /// True when there is no pair.
    pub fn is_empty(&self) -> bool {
        self.reference.is_empty()
    }
}

fn select(traj: &Trajectory, ids: &[usize]) -> Trajectory {
    Trajectory {
        stamps: ids.iter().map(|&i| traj.stamps[i]).collect(),
        poses: ids.iter().map(|&i| traj.poses[i]).collect(),
    }
}

/// Indices of best-matching stamps, exactly as evo's `sync.matching_time_indices`.
///
/// For each stamp of `stamps_1`, the nearest stamp of `stamps_2 + offset_2` within
/// `max_diff` (ties go to the earlier stamp). Binary search when `stamps_2` is sorted,
/// linear search otherwise. Like evo, a stamp of `stamps_2` can be matched more than once
/// when `stamps_1` is denser than `2 · max_diff`.
pub fn matching_time_indices(
    stamps_1: &[f64],
    stamps_2: &[f64],
    max_diff: f64,
    offset_2: f64,
) -> (Vec<usize>, Vec<usize>) {
    let shifted: Vec<f64> = stamps_2.iter().map(|s| s + offset_2).collect();
    let matcher = if shifted.windows(2).all(|w| w[1] - w[0] >= 0.0) {
        nearest_sorted
    } else {
        nearest_linear
    };
    stamps_1
        .iter()
        .enumerate()
        .filter_map(|(i, &s)| matcher(&shifted, s, max_diff).map(|j| (i, j)))
        .unzip()
}

fn nearest_linear(stamps: &[f64], stamp: f64, max_diff: f64) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (j, s) in stamps.iter().enumerate() {
        let diff = (s - stamp).abs();
        if best.is_none_or(|(_, d)| diff < d) {
            best = Some((j, diff));
        }
    }
    best.filter(|&(_, d)| d <= max_diff).map(|(j, _)| j)
}

fn nearest_sorted(stamps: &[f64], stamp: f64, max_diff: f64) -> Option<usize> {
    let (first, last) = (*stamps.first()?, *stamps.last()?);
    if stamp < first - max_diff || stamp > last + max_diff {
        return None;
    }
    let index = stamps
        .partition_point(|&s| s <= stamp)
        .min(stamps.len() - 1);
    let diff_ub = stamps[index] - stamp;
    let diff_lb = if index > 0 {
        stamp - stamps[index - 1]
    } else {
        f64::INFINITY
    };
    if diff_ub <= max_diff && diff_ub < diff_lb {
        Some(index)
    } else if diff_lb <= max_diff && diff_lb <= diff_ub {
        Some(index - 1)
    } else {
        None
    }
}

/// Associates by stamp with the labels "reference" and "estimate" in errors.
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// use keylo_eval::associate::{associate, AssociateOptions};
/// let mut gt = Trajectory::default();
/// let mut est = Trajectory::default();
/// for i in 0..5 { gt.push(i as f64 * 0.1, Pose::identity()); }
/// for i in 1..5 { est.push(i as f64 * 0.1 + 0.004, Pose::identity()); }
/// let pairs = associate(&gt, &est, &AssociateOptions::default())?;
/// assert_eq!(pairs.reference_indices, vec![1, 2, 3, 4]);
/// assert_eq!(pairs.estimate_indices, vec![0, 1, 2, 3]);
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
pub fn associate(
    reference: &Trajectory,
    estimate: &Trajectory,
    opts: &AssociateOptions,
) -> Result<Associated, EvalError> {
    associate_labeled(reference, "reference", estimate, "estimate", opts)
}

/// Associates by stamp like evo's `associate_trajectories(traj_ref, traj_est)`.
///
/// The shorter trajectory drives the search (the estimate when lengths are equal), so
/// none of its poses is lost; `opts.offset` shifts the estimate. Fails with an error that
/// names both labels when nothing matches.
pub fn associate_labeled(
    reference: &Trajectory,
    reference_label: &str,
    estimate: &Trajectory,
    estimate_label: &str,
    opts: &AssociateOptions,
) -> Result<Associated, EvalError> {
    check_options(opts)?;
    let second_longer = estimate.len() > reference.len();
    let (ref_ids, est_ids) = if second_longer {
        matching_time_indices(
            &reference.stamps,
            &estimate.stamps,
            opts.max_diff,
            opts.offset,
        )
    } else {
        let (est, refs) = matching_time_indices(
            &estimate.stamps,
            &reference.stamps,
            opts.max_diff,
            -opts.offset,
        );
        (refs, est)
    };
    if ref_ids.is_empty() {
        return Err(EvalError::NoMatches {
            reference: reference_label.to_string(),
            estimate: estimate_label.to_string(),
            max_diff: opts.max_diff,
            offset: opts.offset,
        });
    }
    Ok(Associated::from_indices(
        reference, estimate, ref_ids, est_ids,
    ))
}

fn check_options(opts: &AssociateOptions) -> Result<(), EvalError> {
    if !(opts.max_diff.is_finite() && opts.max_diff >= 0.0) {
        return Err(EvalError::InvalidOption {
            name: "max_diff",
            reason: format!(
                "{} is not a finite, non-negative number of seconds",
                opts.max_diff
            ),
        });
    }
    if !opts.offset.is_finite() {
        return Err(EvalError::InvalidOption {
            name: "offset",
            reason: format!("{} is not finite", opts.offset),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Pose;

    fn traj(stamps: &[f64]) -> Trajectory {
        let mut t = Trajectory::default();
        for &s in stamps {
            t.push(s, Pose::translation(s, 0.0, 0.0));
        }
        t
    }

    #[test]
    fn sorted_matching_picks_nearest_within_max_diff() {
        let (a, b) = matching_time_indices(&[0.0, 0.05, 0.104, 0.3], &[0.0, 0.1, 0.2], 0.01, 0.0);
        assert_eq!(a, vec![0, 2]);
        assert_eq!(b, vec![0, 1]);
    }

    #[test]
    fn tie_goes_to_earlier_stamp() {
        let (_, b) = matching_time_indices(&[0.5], &[0.0, 0.25, 0.75], 0.3, 0.0);
        assert_eq!(b, vec![1]);
    }

    #[test]
    fn unsorted_falls_back_to_linear_search() {
        let (a, b) = matching_time_indices(&[0.1, 0.2], &[0.2, 0.0, 0.1], 0.01, 0.0);
        assert_eq!(a, vec![0, 1]);
        assert_eq!(b, vec![2, 0]);
    }

    #[test]
    fn offset_shifts_estimate() {
        let gt = traj(&[1.0, 2.0, 3.0]);
        let est = traj(&[0.5, 1.5, 2.5]);
        let opts = AssociateOptions {
            max_diff: 0.01,
            offset: 0.5,
        };
        let pairs = associate(&gt, &est, &opts).unwrap();
        assert_eq!(pairs.reference_indices, vec![0, 1, 2]);
        assert_eq!(pairs.estimate.stamps, vec![0.5, 1.5, 2.5]);
    }

    #[test]
    fn no_match_names_both_labels() {
        let err = associate_labeled(
            &traj(&[0.0]),
            "gt.tum",
            &traj(&[5.0]),
            "est.tum",
            &AssociateOptions::default(),
        );
        let msg = err.unwrap_err().to_string();
        assert!(msg.contains("gt.tum") && msg.contains("est.tum"), "{msg}");
    }

    #[test]
    fn edited_pairs_are_checked() {
        let mut pairs = Associated::by_index(&traj(&[0.0, 1.0]), &traj(&[0.0, 1.0])).unwrap();
        pairs.estimate.poses.pop();
        assert!(matches!(
            pairs.ensure_paired(),
            Err(EvalError::LengthMismatch { .. })
        ));
    }

    #[test]
    fn by_index_needs_equal_lengths() {
        assert!(Associated::by_index(&traj(&[0.0]), &traj(&[0.0, 1.0])).is_err());
        assert_eq!(
            Associated::by_index(&traj(&[0.0, 1.0]), &traj(&[5.0, 6.0]))
                .unwrap()
                .len(),
            2
        );
    }
}
