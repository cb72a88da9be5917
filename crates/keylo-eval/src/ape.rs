//! Absolute pose error (ATE), as `evo_ape` (with `-a` / `-as` for alignment).

use keylo_core::Trajectory;

use crate::align::Alignment;
use crate::align_roll::align_trajectory;
use crate::associate::Associated;
use crate::pose_error::{relative, PoseRelation};
use crate::stats::Stats;
use crate::EvalError;

/// How the estimate is aligned to the reference before APE.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub enum AlignMode {
    /// No alignment (evo default without flags).
    None,
    /// SE(3) Umeyama alignment (evo `-a`).
    #[default]
    Se3,
    /// Sim(3) Umeyama alignment (evo `-as`).
    Sim3,
}

/// Options of [`ape`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct ApeOptions {
    /// Alignment before computing errors (default SE(3), i.e. `evo_ape -a`).
    pub align: AlignMode,
}

/// APE of both pose relations.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ApeResult {
    /// Statistics of the translation errors, metres (evo `trans_part`).
    pub translation: Stats,
    /// Statistics of the rotation angle errors, degrees (evo `angle_deg`).
    pub rotation_deg: Stats,
    /// The alignment applied to the estimate.
    pub alignment: Alignment,
    /// Per-pair translation errors, metres.
    pub translation_errors: Vec<f64>,
    /// Per-pair rotation errors, degrees.
    pub rotation_errors_deg: Vec<f64>,
}

/// Aligns the estimate as asked and returns the alignment used.
pub fn alignment_for(pairs: &Associated, mode: AlignMode) -> Result<Alignment, EvalError> {
    match mode {
        AlignMode::None => Ok(Alignment::identity()),
        AlignMode::Se3 => align_trajectory(&pairs.estimate, &pairs.reference, false),
        AlignMode::Sim3 => align_trajectory(&pairs.estimate, &pairs.reference, true),
    }
}

/// Per-pair APE between `reference` (`Q`) and an already aligned `estimate` (`P`), paired
/// pose for pose: `‖tᴾᵢ − tQᵢ‖` for [`PoseRelation::Translation`] (evo compares positions),
/// the rotation angle of `Pᵢ⁻¹ Qᵢ` for [`PoseRelation::AngleDeg`] (evo `APE.ape_base`).
pub fn ape_errors(
    reference: &Trajectory,
    estimate: &Trajectory,
    relation: PoseRelation,
) -> Vec<f64> {
    let pairs = reference.poses.iter().zip(&estimate.poses);
    match relation {
        PoseRelation::Translation => pairs
            .map(|(q, p)| (p.translation.vector - q.translation.vector).norm())
            .collect(),
        PoseRelation::AngleDeg => pairs.map(|(q, p)| relation.of(&relative(p, q))).collect(),
    }
}

/// APE after association and alignment.
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// use keylo_eval::{ape::{ape, ApeOptions}, associate::Associated};
/// let mut gt = Trajectory::default();
/// let mut est = Trajectory::default();
/// for i in 0..10 {
///     let p = Pose::translation(i as f64, (i * i) as f64 * 0.1, (i % 3) as f64);
///     gt.push(i as f64, p);
///     est.push(i as f64, Pose::translation(7.0, -1.0, 2.0) * p); // rigidly moved copy
/// }
/// let result = ape(&Associated::by_index(&gt, &est)?, &ApeOptions::default())?;
/// assert!(result.translation.rmse < 1e-9);
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
pub fn ape(pairs: &Associated, opts: &ApeOptions) -> Result<ApeResult, EvalError> {
    pairs.ensure_paired()?;
    let alignment = alignment_for(pairs, opts.align)?;
    let aligned = alignment.apply_trajectory(&pairs.estimate);
    let translation_errors = ape_errors(&pairs.reference, &aligned, PoseRelation::Translation);
    let rotation_errors_deg = ape_errors(&pairs.reference, &aligned, PoseRelation::AngleDeg);
    Ok(ApeResult {
        translation: Stats::from_errors(&translation_errors)?,
        rotation_deg: Stats::from_errors(&rotation_errors_deg)?,
        alignment,
        translation_errors,
        rotation_errors_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Pose;

    fn line_with_wiggle(offset: f64) -> Trajectory {
        let mut t = Trajectory::default();
        for i in 0..6 {
            t.push(
                i as f64,
                Pose::translation(i as f64 + offset, (i % 2) as f64, (i / 3) as f64),
            );
        }
        t
    }

    #[test]
    fn unaligned_shift_is_measured() {
        let pairs = Associated::by_index(&line_with_wiggle(0.0), &line_with_wiggle(0.5)).unwrap();
        let r = ape(
            &pairs,
            &ApeOptions {
                align: AlignMode::None,
            },
        )
        .unwrap();
        assert!((r.translation.rmse - 0.5).abs() < 1e-12);
        assert!(r.rotation_deg.max < 1e-12);
        let r = ape(&pairs, &ApeOptions::default()).unwrap();
        assert!(r.translation.rmse < 1e-12);
    }

    #[test]
    fn too_few_poses_to_align() {
        let mut t = Trajectory::default();
        t.push(0.0, Pose::identity());
        t.push(1.0, Pose::translation(1.0, 0.0, 0.0));
        let pairs = Associated::by_index(&t, &t).unwrap();
        assert!(matches!(
            ape(&pairs, &ApeOptions::default()),
            Err(EvalError::TooFewPoints { found: 2 })
        ));
    }
}
