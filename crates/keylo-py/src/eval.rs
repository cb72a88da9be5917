//! `keylo.evaluate`: ATE/RPE/drift of an estimate against a reference, as `keylo eval`.

use std::path::PathBuf;

use keylo::eval::ape::AlignMode;
use keylo::eval::associate::AssociateOptions;
use keylo::eval::{evaluate as evaluate_rs, EvalOptions};
use keylo::io::trajectory::{reconcile, Format, Labelled};
use keylo::{Pose, Trajectory};
use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::arrays::vector_f64;
use crate::errors::{DataError, KeyloError};

/// A trajectory argument: a TUM/KITTI file, or an N×4×4 array with `stamps` (None: the
/// pose indices, paired one for one with the other trajectory).
pub fn trajectory_of(
    obj: &Bound<'_, PyAny>,
    stamps: Option<&Bound<'_, PyAny>>,
    what: &str,
) -> PyResult<Labelled> {
    if let Ok(path) = obj.extract::<PathBuf>() {
        return Labelled::read(&path).map_err(|e| DataError::new_err(e.to_string()));
    }
    let np = obj.py().import("numpy")?;
    let arr = np
        .call_method1("asarray", (obj, "float64"))
        .and_then(|a| a.extract::<PyReadonlyArray3<f64>>())
        .map_err(|_| {
            DataError::new_err(format!("{what}: expected a file path or an N×4×4 array"))
        })?;
    let shape = arr.shape();
    if shape[1..] != [4, 4] {
        return Err(DataError::new_err(format!(
            "{what}: expected an N×4×4 array, got {}×{}×{}",
            shape[0], shape[1], shape[2]
        )));
    }
    let a = arr.as_array();
    let mut poses = Vec::with_capacity(shape[0]);
    for k in 0..shape[0] {
        let m: [f64; 16] = std::array::from_fn(|i| a[(k, i / 4, i % 4)]);
        let pose: Pose = keylo::rigid::pose_from_matrix(&m).map_err(|e| {
            DataError::new_err(format!("{what}: pose {k} is not a rigid transform ({e})"))
        })?;
        poses.push(pose);
    }
    let (stamps, format) = match stamps {
        Some(s) => (
            vector_f64(s, &format!("{what} stamps"), poses.len())?,
            Format::Tum,
        ),
        // Like a KITTI file: paired one for one.
        None => ((0..poses.len()).map(|i| i as f64).collect(), Format::Kitti),
    };
    Ok(Labelled {
        trajectory: Trajectory { stamps, poses },
        format,
        label: what.to_string(),
    })
}

/// The estimate and ground truth arguments, read and given comparable stamps as `keylo eval`
/// does (a trajectory without stamps is paired one for one with the other).
pub fn paired(
    est: &Bound<'_, PyAny>,
    est_stamps: Option<&Bound<'_, PyAny>>,
    gt: &Bound<'_, PyAny>,
    gt_stamps: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Labelled, Labelled)> {
    let mut e = trajectory_of(est, est_stamps, "est")?;
    let mut g = trajectory_of(gt, gt_stamps, "gt")?;
    if e.format == Format::Kitti && g.format == Format::Kitti {
        // Neither has stamps: both count poses.
        e.trajectory.stamps = (0..e.trajectory.len()).map(|i| i as f64).collect();
        g.trajectory.stamps = (0..g.trajectory.len()).map(|i| i as f64).collect();
    }
    reconcile(&mut e, &mut g).map_err(|err| DataError::new_err(err.to_string()))?;
    Ok((e, g))
}

/// `keylo.evaluate(est, gt, est_stamps=None, gt_stamps=None, align="se3", t_max_diff=0.01,
/// t_offset=0.0, rpe_delta=1)`: the figures `keylo eval` prints, as a dict (`ate_rmse_m`,
/// `rpe_trans_rmse_m`, `drift_pct`, …). `est`/`gt` are TUM/KITTI files or N×4×4 arrays.
#[pyfunction]
#[pyo3(signature = (est, gt, est_stamps=None, gt_stamps=None, align="se3", t_max_diff=0.01, t_offset=0.0, rpe_delta=1))]
#[allow(clippy::too_many_arguments)] // keyword arguments of one Python function
pub fn evaluate<'py>(
    py: Python<'py>,
    est: &Bound<'py, PyAny>,
    gt: &Bound<'py, PyAny>,
    est_stamps: Option<&Bound<'py, PyAny>>,
    gt_stamps: Option<&Bound<'py, PyAny>>,
    align: &str,
    t_max_diff: f64,
    t_offset: f64,
    rpe_delta: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let align = match align {
        "se3" => AlignMode::Se3,
        "sim3" => AlignMode::Sim3,
        "none" => AlignMode::None,
        other => {
            return Err(DataError::new_err(format!(
                "align = {other:?}: expected \"se3\", \"sim3\" or \"none\""
            )))
        }
    };
    if rpe_delta == 0 {
        return Err(DataError::new_err(
            "rpe_delta = 0: expected 1 or more frames",
        ));
    }
    let (e, g) = paired(est, est_stamps, gt, gt_stamps)?;
    let opts = EvalOptions {
        associate: AssociateOptions {
            max_diff: t_max_diff,
            offset: t_offset,
        },
        align,
        rpe_delta_frames: rpe_delta,
        reference_label: g.label.clone(),
        estimate_label: e.label.clone(),
        ..EvalOptions::default()
    };
    let (et, gtr) = (&e.trajectory, &g.trajectory);
    let (acc, coverage) = py
        .detach(|| {
            let coverage = keylo::eval::coverage::of_evaluation(et, gtr, &opts);
            evaluate_rs(et, gtr, &opts).map(|acc| (acc, coverage))
        })
        .map_err(|err| DataError::new_err(err.to_string()))?;
    // As `keylo eval` names the reference: the file's name (an array is "gt").
    let label = gt
        .extract::<PathBuf>()
        .ok()
        .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .unwrap_or_else(|| g.label.clone());
    let doc = keylo::eval::coverage::EvalDocument {
        accuracy: &acc,
        reference_label: &label,
        association: &coverage,
    };
    let json = serde_json::to_string(&doc).map_err(|err| KeyloError::new_err(err.to_string()))?;
    py.import("json")?.call_method1("loads", (json,))
}
