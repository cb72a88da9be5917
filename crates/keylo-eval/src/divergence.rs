//! Whether a run diverged, the way `keylo compare` judges its runs (and `keylo.compare` from
//! Python, with the same numbers): a pose that is not finite, one step between consecutive
//! poses longer than a bound, or an aligned translation error (APE, `evo_ape -a`) larger than
//! a bound.

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

/// The verdict on `estimate` and why. `max_ape_m` is its largest aligned translation error
/// ([`aligned_ape`]), `None` without one; `has_ground_truth` says whether there was ground
/// truth to pair with (for the reason given).
pub fn judge(
    estimate: &Trajectory,
    max_ape_m: Option<f64>,
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
    match max_ape_m {
        Some(m) if m > criterion.max_ape_m => (
            Verdict::Diverged,
            format!("max APE {m:.2} m > {} m", criterion.max_ape_m),
        ),
        Some(m) => (
            Verdict::Ok,
            format!("max APE {m:.3} m, largest step {step:.2} m"),
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
        let (v, why) = judge(&line(&[1.0, 1.0]), Some(0.5), true, &c);
        assert_eq!(
            (v, why.as_str()),
            (Verdict::Ok, "max APE 0.500 m, largest step 1.00 m")
        );
        let (v, why) = judge(&line(&[1.0, 6.0]), Some(0.5), true, &c);
        assert_eq!(
            (v, why.as_str()),
            (Verdict::Diverged, "a step of 6.00 m > 5 m")
        );
        let (v, why) = judge(&line(&[1.0]), Some(2.5), true, &c);
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
}
