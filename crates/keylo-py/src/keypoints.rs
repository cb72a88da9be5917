//! `keylo.keypoints.evaluate`: the paper's six keypoint metrics on images given from Python,
//! as `keylo keypoints eval` computes them.

use std::path::PathBuf;

use keylo::config::Trust;
use keylo::kpeval::{evaluate, parse_combos, summarise, ComboSet, EvalOptions, EvalSpec, Plane};
use keylo::BuildContext;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::errors::{ConfigError, DataError, KeyloError, StageError};

/// The spec: None (the paper's), TOML text, or a `.toml` file; one naming an ONNX Runtime
/// library of its own only when `trust` allows it.
fn spec_of(spec: Option<&str>, trust: Trust) -> PyResult<(EvalSpec, PathBuf)> {
    let Some(text) = spec else {
        return Ok((EvalSpec::default(), PathBuf::from(".")));
    };
    let (text, origin, base) = if !text.contains('\n') && text.ends_with(".toml") {
        let path = PathBuf::from(text);
        let body = std::fs::read_to_string(&path)
            .map_err(|e| ConfigError::new_err(format!("{}: {e}", path.display())))?;
        let base = path.parent().map(PathBuf::from).unwrap_or_default();
        (body, path.display().to_string(), base)
    } else {
        (
            text.to_string(),
            "spec text".to_string(),
            PathBuf::from("."),
        )
    };
    let spec =
        EvalSpec::from_toml(&text, &origin).map_err(|e| ConfigError::new_err(e.to_string()))?;
    spec.check_trust(&origin, trust)
        .map_err(|e| ConfigError::new_err(e.to_string()))?;
    Ok((spec, base))
}

/// `keylo.keypoints.evaluate(images, combos="paper", spec=None, jobs=1)`: `images` are 8-bit
/// H×W arrays of one sequence (each paired with the previous for the matching metrics);
/// `combos` is `paper`, `all` or names like `AKAZE_AKAZE,FAST_BRIEF`; `spec` is a keypoint
/// evaluation spec (TOML text or file; None: the paper's settings). Returns `(rows,
/// summaries, skipped)`: one dict per image and combination (the columns of
/// `per_image.csv`), one per combination with every metric's quartiles, and the
/// combinations this build cannot make with why. A spec naming an ONNX Runtime library of
/// its own (`[params.<kind>] onnxruntime`) is refused unless `trust_plugins=True`.
#[pyfunction]
#[pyo3(signature = (images, combos="paper", spec=None, jobs=1, *, trust_plugins=false))]
pub fn evaluate_keypoints<'py>(
    py: Python<'py>,
    images: &Bound<'py, PyAny>,
    combos: &str,
    spec: Option<&str>,
    jobs: usize,
    trust_plugins: bool,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyList>)> {
    let mut planes = Vec::new();
    for (i, item) in images.try_iter()?.enumerate() {
        let item = item?;
        let arr: PyReadonlyArray2<u8> = item
            .extract()
            .map_err(|_| DataError::new_err(format!("images[{i}]: expected an H×W uint8 array")))?;
        let shape = arr.shape();
        planes.push(Plane {
            rows: shape[0],
            cols: shape[1],
            data: arr.as_array().iter().copied().collect(),
            label: i.to_string(),
        });
    }
    let trust = Trust::opted_in(trust_plugins);
    let (spec, base_dir) = spec_of(spec, trust)?;
    let registry = crate::detectors::registry(py)?;
    let set = ComboSet::parse(combos);
    let combos = parse_combos(&set, &registry).map_err(|e| ConfigError::new_err(e.to_string()))?;
    let ctx = BuildContext { base_dir, trust };
    let opts = EvalOptions {
        jobs: jobs.max(1),
        skip_unavailable: set.skips_unavailable(),
        progress: None,
    };
    let result = py
        .detach(|| evaluate(&planes, &combos, &spec, &registry, &ctx, &opts))
        .map_err(|e| StageError::new_err(e.to_string()))?;
    if let Some((what, error)) = result.failed.first() {
        return Err(StageError::new_err(format!("{what}: {error}")));
    }
    let json = py.import("json")?;
    let to_py = |v: String| json.call_method1("loads", (v,));
    let rows =
        serde_json::to_string(&result.rows).map_err(|e| KeyloError::new_err(e.to_string()))?;
    let summaries = serde_json::to_string(&summarise(&result.rows))
        .map_err(|e| KeyloError::new_err(e.to_string()))?;
    let skipped = PyList::empty(py);
    for s in &result.skipped {
        skipped.append(s.clone())?;
    }
    Ok((to_py(rows)?, to_py(summaries)?, skipped))
}
