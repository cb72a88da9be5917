//! `keylo.judge`: `keylo compare`'s verdict on one run (ok or diverged, and why) with its
//! aligned-APE figures, for `keylo.compare`'s records.

use keylo::eval::divergence::{aligned_ape, judge as judge_rs, verdict_ape, Criterion};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::eval::{paired, trajectory_of};

/// `keylo.judge(est, gt=None, est_stamps=None, gt_stamps=None, max_ape=2.0, max_step=5.0,
/// t_max_diff=0.01)`: a dict with `verdict` (`ok` or `diverged`), `reason`, and without
/// ground truth None, else `associated_poses`, `trans_mean_m`, `trans_rmse_m`, `trans_max_m`,
/// `rot_mean_deg`, `rot_rmse_deg` (SE(3)-aligned APE over poses paired within `t_max_diff`
/// seconds) — the columns `keylo compare` writes, with its bounds.
#[pyfunction]
#[pyo3(signature = (est, gt=None, est_stamps=None, gt_stamps=None, max_ape=2.0, max_step=5.0, t_max_diff=0.01))]
#[allow(clippy::too_many_arguments)] // keyword arguments of one Python function
pub fn judge<'py>(
    py: Python<'py>,
    est: &Bound<'py, PyAny>,
    gt: Option<&Bound<'py, PyAny>>,
    est_stamps: Option<&Bound<'py, PyAny>>,
    gt_stamps: Option<&Bound<'py, PyAny>>,
    max_ape: f64,
    max_step: f64,
    t_max_diff: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let criterion = Criterion {
        max_ape_m: max_ape,
        max_step_m: max_step,
        t_max_diff_s: t_max_diff,
    };
    let out = PyDict::new(py);
    let (estimate, figures) = match gt {
        Some(gt) => {
            let (e, g) = paired(est, est_stamps, gt, gt_stamps)?;
            let found = py.detach(|| {
                let (e, g) = (&e.trajectory, &g.trajectory);
                let ape = aligned_ape(e, g, t_max_diff).ok();
                let for_verdict = verdict_ape(ape.as_ref().map(|(_, r)| r), e, g, t_max_diff);
                (ape, for_verdict)
            });
            (e.trajectory, Some(found))
        }
        None => (trajectory_of(est, est_stamps, "est")?.trajectory, None),
    };
    let has_ground_truth = figures.is_some();
    let (ape, for_verdict) = figures.unwrap_or((None, None));
    let max_ape_m = ape.as_ref().map(|(_, r)| r.translation.max);
    let (verdict, reason) = judge_rs(&estimate, for_verdict, has_ground_truth, &criterion);
    out.set_item("verdict", verdict.as_str())?;
    out.set_item("reason", reason)?;
    out.set_item("associated_poses", ape.as_ref().map(|(p, _)| p.len()))?;
    let stat = |f: fn(&keylo::eval::ape::ApeResult) -> f64| ape.as_ref().map(|(_, r)| f(r));
    out.set_item("trans_mean_m", stat(|r| r.translation.mean))?;
    out.set_item("trans_rmse_m", stat(|r| r.translation.rmse))?;
    out.set_item("trans_max_m", max_ape_m)?;
    out.set_item("rot_mean_deg", stat(|r| r.rotation_deg.mean))?;
    out.set_item("rot_rmse_deg", stat(|r| r.rotation_deg.rmse))?;
    Ok(out)
}
