//! One-call accuracy summary (ATE, RPE, drift) for the CLI and `summary.json`.

use keylo_core::Trajectory;

use crate::ape::{ape, AlignMode, ApeOptions};
use crate::associate::{associate_labeled, AssociateOptions};
use crate::drift::{kitti_drift, DriftOptions};
use crate::rpe::{rpe, Delta, RpeOptions};
use crate::EvalError;

/// Options of [`evaluate`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EvalOptions {
    /// Stamp association (default: max. 0.01 s difference, no offset).
    pub associate: AssociateOptions,
    /// Alignment before ATE (default SE(3), as `evo_ape -a`).
    pub align: AlignMode,
    /// RPE pair spacing in frames (default 1, as `evo_rpe`).
    pub rpe_delta_frames: usize,
    /// Drift segments; `None` (default) picks [`DriftOptions::for_path_length`] of the
    /// associated reference.
    pub drift: Option<DriftOptions>,
    /// Name of the reference in error messages (e.g. its file).
    pub reference_label: String,
    /// Name of the estimate in error messages (e.g. its file).
    pub estimate_label: String,
}

impl Default for EvalOptions {
    fn default() -> Self {
        Self {
            associate: AssociateOptions::default(),
            align: AlignMode::Se3,
            rpe_delta_frames: 1,
            drift: None,
            reference_label: "reference".to_string(),
            estimate_label: "estimate".to_string(),
        }
    }
}

/// Accuracy summary of an estimated trajectory.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Accuracy {
    /// Number of associated pose pairs.
    pub associated_poses: usize,
    /// ATE: RMSE of the aligned translation errors, metres (`evo_ape -a`).
    pub ate_rmse_m: f64,
    /// ATE: mean of the aligned translation errors, metres.
    pub ate_mean_m: f64,
    /// APE rotation: RMSE of the aligned rotation angle errors, degrees.
    pub ate_rot_rmse_deg: f64,
    /// The path is (nearly) straight, so the alignment's rotation about its axis came from
    /// the orientations, not the positions ([`crate::align_roll`]).
    pub alignment_roll_from_orientations: bool,
    /// RPE translation RMSE, metres per `rpe_delta_frames` frames (`evo_rpe`).
    pub rpe_trans_rmse_m: f64,
    /// RPE rotation RMSE, degrees per `rpe_delta_frames` frames.
    pub rpe_rot_rmse_deg: f64,
    /// KITTI-style translation drift, percent (metres per 100 m); `None` when no segment fits.
    pub drift_pct: Option<f64>,
    /// KITTI-style rotation drift, degrees per 100 m; `None` when no segment fits.
    pub drift_deg_per_100m: Option<f64>,
    /// Segment lengths used for drift, metres (empty when none fits).
    pub drift_lengths_m: Vec<f64>,
}

/// Associates, aligns and measures `est` against `gt`.
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// let mut gt = Trajectory::default();
/// let mut est = Trajectory::default();
/// for i in 0..50 {
///     let t = i as f64 * 0.1;
///     gt.push(t, Pose::translation(t.sin() * 5.0, t * 2.0, (2.0 * t).cos()));
///     est.push(t + 0.002, Pose::translation(1.0, 2.0, 3.0) * gt.poses[i]);
/// }
/// let acc = keylo_eval::evaluate(&est, &gt, &Default::default())?;
/// assert_eq!(acc.associated_poses, 50);
/// assert!(acc.ate_rmse_m < 1e-9 && acc.rpe_trans_rmse_m < 1e-9);
/// assert!(acc.drift_pct.is_some());
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
pub fn evaluate(
    est: &Trajectory,
    gt: &Trajectory,
    opts: &EvalOptions,
) -> Result<Accuracy, EvalError> {
    let pairs = associate_labeled(
        gt,
        &opts.reference_label,
        est,
        &opts.estimate_label,
        &opts.associate,
    )?;
    let ate = ape(&pairs, &ApeOptions { align: opts.align })?;
    let rpe_opts = RpeOptions {
        delta: Delta::Frames(opts.rpe_delta_frames),
        ..RpeOptions::default()
    };
    let rel = rpe(&pairs, &rpe_opts)?;
    let drift_opts = match &opts.drift {
        Some(d) => d.clone(),
        None => DriftOptions::for_path_length(pairs.reference.path_length()),
    };
    let drift = match kitti_drift(&pairs, &drift_opts) {
        Ok(d) => Some(d),
        Err(EvalError::NoSegments { .. }) => None,
        Err(e) => return Err(e),
    };
    Ok(Accuracy {
        associated_poses: pairs.len(),
        ate_rmse_m: ate.translation.rmse,
        ate_mean_m: ate.translation.mean,
        ate_rot_rmse_deg: ate.rotation_deg.rmse,
        alignment_roll_from_orientations: ate.alignment.roll_from_orientations,
        rpe_trans_rmse_m: rel.translation.rmse,
        rpe_rot_rmse_deg: rel.rotation_deg.rmse,
        drift_pct: drift.as_ref().map(|d| d.translation_pct),
        drift_deg_per_100m: drift.as_ref().map(|d| d.rotation_deg_per_100m),
        drift_lengths_m: drift.map(|d| d.lengths).unwrap_or_default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Pose;

    #[test]
    fn labels_reach_the_no_match_error() {
        let mut gt = Trajectory::default();
        let mut est = Trajectory::default();
        gt.push(0.0, Pose::identity());
        est.push(9.0, Pose::identity());
        let opts = EvalOptions {
            reference_label: "gt.tum".into(),
            estimate_label: "run.tum".into(),
            ..EvalOptions::default()
        };
        let msg = evaluate(&est, &gt, &opts).unwrap_err().to_string();
        assert!(msg.contains("gt.tum") && msg.contains("run.tum"), "{msg}");
    }
}
