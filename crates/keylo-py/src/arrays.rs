//! numpy arrays in and out.

use keylo::Pose;
use numpy::ndarray::{Array2, Array3, ArrayView, Dimension};
use numpy::{
    Element, IntoPyArray, PyArray, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::errors::DataError;

/// A pose as a 4×4 array.
pub fn pose_matrix(pose: &Pose) -> Array2<f64> {
    let h = pose.to_homogeneous();
    Array2::from_shape_fn((4, 4), |(r, c)| h[(r, c)])
}

/// Poses as an N×4×4 array.
pub fn pose_stack<'py>(py: Python<'py>, poses: &[Pose]) -> Bound<'py, PyArray3<f64>> {
    let mut out = Array3::zeros((poses.len(), 4, 4));
    for (k, p) in poses.iter().enumerate() {
        let h = p.to_homogeneous();
        for r in 0..4 {
            for c in 0..4 {
                out[(k, r, c)] = h[(r, c)];
            }
        }
    }
    out.into_pyarray(py)
}

/// Points as an N×3 array.
pub fn points<'py>(py: Python<'py>, pts: &[nalgebra::Point3<f64>]) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((pts.len(), 3), |(i, k)| pts[i][k]).into_pyarray(py)
}

/// A read-only numpy view of `view`, whose memory `owner` keeps alive and never changes.
///
/// # Safety
/// `view` must point into memory owned by `owner` that is not mutated or freed while `owner`
/// lives (a frozen pyclass).
pub unsafe fn borrowed<'py, T: Element, D: Dimension>(
    view: ArrayView<'_, T, D>,
    owner: Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    // SAFETY: forwarded from the caller.
    let array = unsafe { PyArray::borrow_from_array(&view, owner) };
    array.getattr("flags")?.setattr("writeable", false)?;
    Ok(array)
}

/// `obj` as a float64 N×C array (C in `cols`), converting float32 and other numbers; the
/// error names `what` and the shape found.
pub fn matrix_f64(obj: &Bound<'_, PyAny>, what: &str, cols: &[usize]) -> PyResult<Array2<f64>> {
    let arr = as_float64(obj, what)?;
    let arr: PyReadonlyArray2<f64> = arr.extract().map_err(|_| {
        let shape = obj
            .getattr("shape")
            .map(|s| s.to_string())
            .unwrap_or_else(|_| "no shape".into());
        DataError::new_err(format!(
            "{what}: expected an N×{} array, got shape {shape}",
            alternatives(cols)
        ))
    })?;
    let shape = arr.shape();
    if !cols.contains(&shape[1]) {
        return Err(DataError::new_err(format!(
            "{what}: expected an N×{} array, got {}×{}",
            alternatives(cols),
            shape[0],
            shape[1]
        )));
    }
    Ok(arr.as_array().to_owned())
}

/// `obj` as a float64 vector of length `n`; the error names `what`.
pub fn vector_f64(obj: &Bound<'_, PyAny>, what: &str, n: usize) -> PyResult<Vec<f64>> {
    let np = obj.py().import("numpy")?;
    let arr = np.call_method1("asarray", (obj, "float64"))?;
    let arr: PyReadonlyArray1<f64> = arr
        .extract()
        .map_err(|_| DataError::new_err(format!("{what}: expected a 1-D array of {n} numbers")))?;
    if arr.len() != n {
        return Err(DataError::new_err(format!(
            "{what}: {} values for {n} points (one per point expected)",
            arr.len()
        )));
    }
    Ok(arr.as_array().to_vec())
}

/// `numpy.asarray(obj, float64)`; what numpy cannot convert is a DataError naming `what`.
fn as_float64<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    np.call_method1("asarray", (obj, "float64"))
        .map_err(|e| DataError::new_err(format!("{what}: not an array of numbers ({e})")))
}

fn alternatives(cols: &[usize]) -> String {
    cols.iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(" or N×")
}
