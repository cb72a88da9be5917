//! Relative pose error, as `evo_rpe` (no alignment, consecutive pairs by default).

mod pairs;

pub use pairs::{accumulated_distances, pose_pairs, Delta};

use crate::associate::Associated;
use crate::pose_error::{relative_error, PoseRelation};
use crate::stats::Stats;
use crate::EvalError;

/// Options of [`rpe`]; the defaults are `evo_rpe`'s.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RpeOptions {
    /// Pair spacing (default 1 frame).
    pub delta: Delta,
    /// Use every pair at distance `delta` instead of consecutive pairs (evo `--all_pairs`).
    pub all_pairs: bool,
    /// Choose pairs on the reference instead of the estimate (evo `--pairs_from_reference`;
    /// evo's default, kept here, chooses them on the estimate).
    pub pairs_from_reference: bool,
    /// Relative tolerance for all-pairs metre deltas (evo `--delta_tol`, default 0.1).
    pub rel_delta_tol: f64,
}

impl Default for RpeOptions {
    fn default() -> Self {
        Self {
            delta: Delta::Frames(1),
            all_pairs: false,
            pairs_from_reference: false,
            rel_delta_tol: 0.1,
        }
    }
}

/// RPE of both pose relations.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RpeResult {
    /// Statistics of the translation errors, metres per pair.
    pub translation: Stats,
    /// Statistics of the rotation angle errors, degrees per pair.
    pub rotation_deg: Stats,
    /// The index pairs `(i, j)` into the associated trajectories.
    pub pairs: Vec<(usize, usize)>,
    /// Per-pair translation errors, metres.
    pub translation_errors: Vec<f64>,
    /// Per-pair rotation errors, degrees.
    pub rotation_errors_deg: Vec<f64>,
}

/// Per-pair errors of `relation` for the error poses `(Qᵢ⁻¹ Qⱼ)⁻¹ (Pᵢ⁻¹ Pⱼ)`.
pub fn rpe_errors(pairs: &Associated, ids: &[(usize, usize)], relation: PoseRelation) -> Vec<f64> {
    let (q, p) = (&pairs.reference.poses, &pairs.estimate.poses);
    ids.iter()
        .map(|&(i, j)| relation.of(&relative_error(&q[i], &q[j], &p[i], &p[j])))
        .collect()
}

/// RPE on associated trajectories (no alignment, as `evo_rpe` by default).
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// use keylo_eval::{associate::Associated, rpe::{rpe, RpeOptions}};
/// let mut gt = Trajectory::default();
/// let mut est = Trajectory::default();
/// for i in 0..4 {
///     gt.push(i as f64, Pose::translation(i as f64, 0.0, 0.0));
///     est.push(i as f64, Pose::translation(1.1 * i as f64, 0.0, 0.0)); // 10 % too fast
/// }
/// let r = rpe(&Associated::by_index(&gt, &est)?, &RpeOptions::default())?;
/// assert_eq!(r.pairs, vec![(0, 1), (1, 2), (2, 3)]);
/// assert!((r.translation.rmse - 0.1).abs() < 1e-12);
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
pub fn rpe(pairs: &Associated, opts: &RpeOptions) -> Result<RpeResult, EvalError> {
    pairs.ensure_paired()?;
    let source = if opts.pairs_from_reference {
        &pairs.reference
    } else {
        &pairs.estimate
    };
    let ids = pose_pairs(
        &source.poses,
        opts.delta,
        opts.all_pairs,
        opts.rel_delta_tol,
    )?;
    let translation_errors = rpe_errors(pairs, &ids, PoseRelation::Translation);
    let rotation_errors_deg = rpe_errors(pairs, &ids, PoseRelation::AngleDeg);
    Ok(RpeResult {
        translation: Stats::from_errors(&translation_errors)?,
        rotation_deg: Stats::from_errors(&rotation_errors_deg)?,
        pairs: ids,
        translation_errors,
        rotation_errors_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::{Pose, Trajectory};
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn global_offset_does_not_change_rpe() {
        let mut gt = Trajectory::default();
        let mut est = Trajectory::default();
        let offset = Pose::from_parts(
            Vector3::new(3.0, 1.0, 0.0).into(),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 1.0),
        );
        for i in 0..5 {
            let p = Pose::from_parts(
                Vector3::new(i as f64, 0.0, 0.0).into(),
                UnitQuaternion::from_euler_angles(0.0, 0.0, 0.2 * i as f64),
            );
            gt.push(i as f64, p);
            est.push(i as f64, offset * p);
        }
        let r = rpe(
            &Associated::by_index(&gt, &est).unwrap(),
            &RpeOptions::default(),
        )
        .unwrap();
        assert!(r.translation.max < 1e-12 && r.rotation_deg.max < 1e-9);
    }

    #[test]
    fn single_pose_has_no_pairs() {
        let mut t = Trajectory::default();
        t.push(0.0, Pose::identity());
        let err = rpe(
            &Associated::by_index(&t, &t).unwrap(),
            &RpeOptions::default(),
        )
        .unwrap_err();
        assert!(matches!(err, EvalError::NoPairs { .. }));
    }
}
