//! Whether a run diverged, the way `keylo compare` judges its runs (and `keylo.compare` from
//! Python, with the same numbers): a pose that is not finite, one step between consecutive
//! poses longer than a bound, or an aligned translation error (APE, `evo_ape -a`) larger than
//! a bound. Where SE(3) alignment is impossible (an estimate that never moved has no spread
//! to align), the error is taken with the first poses aligned instead, so a run stuck in place
//! is judged by how far the ground truth went.

use keylo_core::Trajectory;
use serde::Serialize;

use crate::ape::{ape, ApeOptions, ApeResult};
use crate::associate::{associate_labeled, AssociateOptions, Associated};
use crate::EvalError;

/// The bounds a run must stay within.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Criterion {
    /// Largest aligned translation error (APE, metres) a run may reach.
    pub max_ape_m: f64,
    /// Largest translation between consecutive estimated poses, metres.
    pub max_step_m: f64,
    /// Largest stamp difference when pairing estimate and ground truth, seconds (evo
    /// `--t_max_diff`).
    pub t_max_diff_s: f64,
}

impl Default for Criterion {
    /// `keylo compare`'s defaults: 2 m APE, 5 m per step, 0.01 s pairing.
    fn default() -> Self {
        Self {
            max_ape_m: 2.0,
            max_step_m: 5.0,
            t_max_diff_s: 0.01,
        }
    }
}

/// How a finished run fared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Within every bound.
    Ok,
    /// A bound was crossed.
    Diverged,
}

impl Verdict {
    /// `ok` or `diverged`, as the tables print it.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::Diverged => "diverged",
        }
    }
}

/// The largest translation error a verdict is judged on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VerdictApe {
    /// After SE(3) alignment (`evo_ape -a`), metres.
    Aligned(f64),
    /// With the first poses aligned (evo `--align_origin`), metres: where SE(3) alignment is
    /// impossible.
    OriginAligned(f64),
}

impl VerdictApe {
    /// The error, metres.
    pub fn metres(self) -> f64 {
        match self {
            Self::Aligned(m) | Self::OriginAligned(m) => m,
        }
    }
}

/// The largest translation error of `estimate` against `ground_truth` (poses paired within
/// `t_max_diff_s`) with the first pair's poses made to coincide.
pub fn origin_aligned_max(
    estimate: &Trajectory,
    ground_truth: &Trajectory,
    t_max_diff_s: f64,
) -> Result<f64, EvalError> {
    let opts = AssociateOptions {
        max_diff: t_max_diff_s,
        ..AssociateOptions::default()
    };
    let pairs = associate_labeled(ground_truth, "ground truth", estimate, "estimate", &opts)?;
    pairs.ensure_paired()?;
    let (Some(r0), Some(e0)) = (pairs.reference.poses.first(), pairs.estimate.poses.first()) else {
        return Ok(0.0);
    };
    let to_reference = r0 * e0.inverse();
    Ok(pairs
        .reference
        .poses
        .iter()
        .zip(&pairs.estimate.poses)
        .map(|(r, e)| ((to_reference * e).translation.vector - r.translation.vector).norm())
        .fold(0.0, f64::max))
}

/// The error a verdict on `estimate` is judged on: the largest error of its SE(3)-aligned APE
/// (`aligned`, from [`aligned_ape`]) or, where that alignment failed, [`origin_aligned_max`];
/// `None` when the two cannot be paired.
pub fn verdict_ape(
    aligned: Option<&ApeResult>,
    estimate: &Trajectory,
    ground_truth: &Trajectory,
    t_max_diff_s: f64,
) -> Option<VerdictApe> {
    match aligned {
        Some(result) => Some(VerdictApe::Aligned(result.translation.max)),
        None => origin_aligned_max(estimate, ground_truth, t_max_diff_s)
            .ok()
            .map(VerdictApe::OriginAligned),
    }
}

/// An estimate's APE against ground truth: the pairs (stamps within `t_max_diff_s`) and the
/// error after SE(3) Umeyama alignment, as `evo_ape -a`.
pub fn aligned_ape(
    estimate: &Trajectory,
    ground_truth: &Trajectory,
    t_max_diff_s: f64,
) -> Result<(Associated, ApeResult), EvalError> {
    let opts = AssociateOptions {
        max_diff: t_max_diff_s,
        ..AssociateOptions::default()
    };
    let pairs = associate_labeled(ground_truth, "ground truth", estimate, "estimate", &opts)?;
    let result = ape(&pairs, &ApeOptions::default())?;
    Ok((pairs, result))
}

/// The verdict on `estimate` and why. `ape` is its largest translation error against ground
/// truth ([`verdict_ape`]), `None` without one; `has_ground_truth` says whether there was
/// ground truth to pair with (for the reason given).
pub fn judge(
    estimate: &Trajectory,
    ape: Option<VerdictApe>,
    has_ground_truth: bool,
    criterion: &Criterion,
) -> (Verdict, String) {
    if !estimate.poses.iter().all(keylo_core::rigid::is_finite) {
        return (Verdict::Diverged, "a pose is not finite".into());
    }
    let step = estimate
        .poses
        .windows(2)
        .map(|w| (w[1].translation.vector - w[0].translation.vector).norm())
        .fold(0.0, f64::max);
    if step > criterion.max_step_m {
        return (
            Verdict::Diverged,
            format!("a step of {step:.2} m > {} m", criterion.max_step_m),
        );
    }
    let how = match ape {
        Some(VerdictApe::OriginAligned(_)) => " (first poses aligned: SE(3) alignment impossible)",
        _ => "",
    };
    match ape.map(VerdictApe::metres) {
        Some(m) if m > criterion.max_ape_m => (
            Verdict::Diverged,
            format!("max APE {m:.2} m > {} m{how}", criterion.max_ape_m),
        ),
        Some(m) => (
            Verdict::Ok,
            format!("max APE {m:.3} m{how}, largest step {step:.2} m"),
        ),
        None if has_ground_truth => (Verdict::Ok, "no APE (trajectory not associable)".into()),
        None => (Verdict::Ok, "no ground truth: step check only".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Pose;
    use nalgebra::{Translation3, UnitQuaternion};

    fn line(steps: &[f64]) -> Trajectory {
        let mut x = 0.0;
        let mut poses = vec![Pose::identity()];
        for s in steps {
            x += s;
            poses.push(Pose::from_parts(
                Translation3::new(x, 0.0, 0.0),
                UnitQuaternion::identity(),
            ));
        }
        Trajectory {
            stamps: (0..poses.len()).map(|i| i as f64 * 0.1).collect(),
            poses,
        }
    }

    #[test]
    fn each_bound_gives_its_reason() {
        let c = Criterion::default();
        let (v, why) = judge(&line(&[1.0, 1.0]), Some(VerdictApe::Aligned(0.5)), true, &c);
        assert_eq!(
            (v, why.as_str()),
            (Verdict::Ok, "max APE 0.500 m, largest step 1.00 m")
        );
        let (v, why) = judge(&line(&[1.0, 6.0]), Some(VerdictApe::Aligned(0.5)), true, &c);
        assert_eq!(
            (v, why.as_str()),
            (Verdict::Diverged, "a step of 6.00 m > 5 m")
        );
        let (v, why) = judge(&line(&[1.0]), Some(VerdictApe::Aligned(2.5)), true, &c);
        assert_eq!(
            (v, why.as_str()),
            (Verdict::Diverged, "max APE 2.50 m > 2 m")
        );
        let (v, why) = judge(&line(&[1.0, f64::NAN]), None, false, &c);
        assert_eq!(
            (v, why.as_str()),
            (Verdict::Diverged, "a pose is not finite")
        );
        let (v, why) = judge(&line(&[1.0]), None, false, &c);
        assert_eq!(
            (v, why.as_str()),
            (Verdict::Ok, "no ground truth: step check only")
        );
    }

    #[test]
    fn aligned_ape_of_a_shifted_copy_is_zero() {
        let gt = line(&[1.0, 0.5, 2.0]);
        let mut est = gt.clone();
        for p in &mut est.poses {
            p.translation.vector.y += 3.0;
        }
        let (pairs, r) = aligned_ape(&est, &gt, 0.01).expect("pairs");
        assert_eq!(pairs.len(), 4);
        assert!(r.translation.max < 1e-9, "{}", r.translation.max);
    }

    #[test]
    fn a_run_that_never_moved_is_judged_with_the_first_poses_aligned() {
        let gt = line(&[1.0, 1.0, 1.0]);
        let stuck = line(&[0.0, 0.0, 0.0]);
        // SE(3) alignment needs the estimate to spread in space.
        assert!(aligned_ape(&stuck, &gt, 0.01).is_err());
        let ape = verdict_ape(None, &stuck, &gt, 0.01);
        assert_eq!(ape, Some(VerdictApe::OriginAligned(3.0)));
        let (v, why) = judge(&stuck, ape, true, &Criterion::default());
        assert_eq!(
            (v, why.as_str()),
            (
                Verdict::Diverged,
                "max APE 3.00 m > 2 m (first poses aligned: SE(3) alignment impossible)"
            )
        );
        // Standing still against a still ground truth is no error.
        let still = verdict_ape(None, &stuck, &line(&[0.0, 0.0, 0.0]), 0.01);
        assert_eq!(still, Some(VerdictApe::OriginAligned(0.0)));
        assert_eq!(
            judge(&stuck, still, true, &Criterion::default()).0,
            Verdict::Ok
        );
        // A moving estimate keeps the SE(3)-aligned figure.
        let (_, aligned) = aligned_ape(&gt, &gt, 0.01).expect("pairs");
        let moved = verdict_ape(Some(&aligned), &gt, &gt, 0.01);
        assert!(
            matches!(moved, Some(VerdictApe::Aligned(m)) if m < 1e-9),
            "{moved:?}"
        );
    }
}
