//! `keylo.Frame` and `keylo.open`: the frames of any source keylo reads, as numpy arrays.

use std::path::PathBuf;
use std::sync::Mutex;

use keylo::config::RawConfig;
use keylo::{ImageSource, LidarFrame};
use numpy::ndarray::{Array2, ArrayView1, ArrayView2, ArrayView3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use pyo3::exceptions::PyStopIteration;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{borrowed, pose_stack};
use crate::config::table_of;
use crate::errors::{config, core, DataError};

/// One frame: the organised grids (`rows`×`cols`) and, for unorganised sources, every point
/// of the scan. Arrays are read-only views of the frame's memory (no copy).
#[pyclass(frozen, module = "keylo")]
pub struct Frame {
    pub(crate) inner: LidarFrame,
}

/// A read-only rows×cols view of one grid of the frame owned by `slf`.
fn grid<'py, T: numpy::Element>(
    slf: &Bound<'py, Frame>,
    field: impl Fn(&LidarFrame) -> &Vec<T>,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let f = &slf.get().inner;
    let view = ArrayView2::from_shape((f.rows, f.cols), field(f).as_slice())
        .map_err(|e| DataError::new_err(e.to_string()))?;
    // SAFETY: the view is of the frozen frame's own data, owned by `slf`.
    unsafe { borrowed(view, slf.clone().into_any()) }
}

#[pymethods]
impl Frame {
    /// Index of the frame in its source.
    #[getter]
    fn index(&self) -> u64 {
        self.inner.index
    }

    /// Time of the frame (first column), seconds.
    #[getter]
    fn timestamp(&self) -> f64 {
        self.inner.timestamp
    }

    /// Grid rows (beams).
    #[getter]
    fn rows(&self) -> usize {
        self.inner.rows
    }

    /// Grid columns.
    #[getter]
    fn cols(&self) -> usize {
        self.inner.cols
    }

    /// Range per pixel, metres (rows×cols float32).
    #[getter]
    fn range<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        grid(slf, |f| &f.range)
    }

    /// Signal (intensity) per pixel (rows×cols float32).
    #[getter]
    fn signal<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        grid(slf, |f| &f.signal)
    }

    /// Reflectivity per pixel (rows×cols float32).
    #[getter]
    fn reflectivity<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        grid(slf, |f| &f.reflectivity)
    }

    /// Near-infrared per pixel (rows×cols float32).
    #[getter]
    fn near_ir<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        grid(slf, |f| &f.near_ir)
    }

    /// Whether each pixel holds a return (rows×cols bool).
    #[getter]
    fn valid<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<bool>>> {
        grid(slf, |f| &f.valid)
    }

    /// The point of each pixel in the sensor frame, metres (rows×cols×3 float32).
    #[getter]
    fn xyz<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let f = &slf.get().inner;
        // SAFETY: `Point3<f32>` is `#[repr(C)]`, three contiguous f32.
        let flat: &[f32] = unsafe {
            std::slice::from_raw_parts(f.points.as_ptr().cast::<f32>(), 3 * f.points.len())
        };
        let view = ArrayView3::from_shape((f.rows, f.cols, 3), flat)
            .map_err(|e| DataError::new_err(e.to_string()))?;
        // SAFETY: the view is of the frozen frame's own data, owned by `slf`.
        unsafe { borrowed(view, slf.clone().into_any()) }
    }

    /// Firing time of each column, absolute seconds (cols float64).
    #[getter]
    fn column_times<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let f = &slf.get().inner;
        // SAFETY: the view is of the frozen frame's own data, owned by `slf`.
        unsafe { borrowed(ArrayView1::from(&f.column_times), slf.clone().into_any()) }
    }

    /// Firing time of every pixel, absolute seconds (rows×cols float64), or None when every
    /// pixel fired at its column's time (`column_times`). A destaggered Ouster frame's rows
    /// fired at their own column offsets; their times are computed on access (a new array).
    #[getter]
    fn pixel_times<'py>(
        slf: &Bound<'py, Self>,
        py: Python<'py>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let f = &slf.get().inner;
        let Some(times) = f.pixel_times_or_lagged() else {
            return Ok(None);
        };
        let grid = Array2::from_shape_vec((f.rows, f.cols), times.into_owned())
            .map_err(|e| DataError::new_err(e.to_string()))?;
        Ok(Some(grid.into_pyarray(py)))
    }

    /// Every finite point of an unorganised scan, file order (N×3 float64), or None for an
    /// organised source (use `xyz` and `valid`).
    #[getter]
    fn points<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let Some(scan) = slf.get().inner.scan.as_ref() else {
            return Ok(None);
        };
        // SAFETY: `Point3<f64>` is `#[repr(C)]`, three contiguous f64.
        let flat: &[f64] = unsafe {
            std::slice::from_raw_parts(scan.points.as_ptr().cast::<f64>(), 3 * scan.points.len())
        };
        let view = ArrayView2::from_shape((scan.points.len(), 3), flat)
            .map_err(|e| DataError::new_err(e.to_string()))?;
        // SAFETY: the scan is shared (Arc) by the frozen frame owned by `slf`.
        unsafe { borrowed(view, slf.clone().into_any()) }.map(Some)
    }

    /// Per-point times of the scan, seconds relative to `timestamp`, or None.
    #[getter]
    fn point_times<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let Some(times) = slf.get().inner.scan.as_ref().and_then(|s| s.times.as_ref()) else {
            return Ok(None);
        };
        // SAFETY: the scan is shared (Arc) by the frozen frame owned by `slf`.
        unsafe { borrowed(ArrayView1::from(times), slf.clone().into_any()) }.map(Some)
    }

    fn __repr__(&self) -> String {
        let f = &self.inner;
        let scan = f
            .scan
            .as_ref()
            .map_or(String::new(), |s| format!(", scan_points={}", s.len()));
        format!(
            "Frame(index={}, timestamp={:.6}, rows={}, cols={}{scan})",
            f.index, f.timestamp, f.rows, f.cols
        )
    }
}

/// Stamps (N) and poses (N×4×4).
type Stamped<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray3<f64>>);

/// The frames of a source, in order; iterate it. `ground_truth()` gives the source's ground
/// truth (the simulator, KITTI with poses) as `(stamps, N×4×4)`, or None.
#[pyclass(module = "keylo")]
pub struct Reader {
    source: Mutex<Box<dyn ImageSource>>,
}

#[pymethods]
impl Reader {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&self, py: Python<'_>) -> PyResult<Frame> {
        let mut source = self
            .source
            .lock()
            .map_err(|_| DataError::new_err("the reader failed earlier"))?;
        let source: &mut Box<dyn ImageSource> = &mut source;
        match py.detach(move || source.next_frame()) {
            None => Err(PyStopIteration::new_err(())),
            Some(Ok(inner)) => Ok(Frame { inner }),
            Some(Err(e)) => Err(core(e)),
        }
    }

    /// `(stamps, poses)`: the ground truth as an N array and an N×4×4 array, or None.
    fn ground_truth<'py>(&self, py: Python<'py>) -> PyResult<Option<Stamped<'py>>> {
        let source = self
            .source
            .lock()
            .map_err(|_| DataError::new_err("the reader failed earlier"))?;
        Ok(source.ground_truth().map(|t| {
            (
                PyArray1::from_vec(py, t.stamps.clone()),
                pose_stack(py, &t.poses),
            )
        }))
    }
}

/// `keylo.open(path=None, kind=None, **keys)`: the frames of `path` (its kind detected as
/// `keylo run --data` does: pcap, bag, mcap, KITTI, PLY/PCD, frame folder) or of source
/// `kind` (e.g. `"sim"`), with more `[source]` keys (`meta`, `start`, `max_frames`, …).
#[pyfunction]
#[pyo3(signature = (path=None, kind=None, **keys))]
pub fn open(
    path: Option<PathBuf>,
    kind: Option<String>,
    keys: Option<&Bound<'_, PyDict>>,
) -> PyResult<Reader> {
    let mut table = match keys {
        Some(k) => table_of(k, ".source")?,
        None => toml::Table::new(),
    };
    let registry = keylo::registry();
    match (kind, &path) {
        (Some(k), p) => {
            table.insert("kind".into(), k.into());
            if let Some(p) = p {
                let abs = std::path::absolute(p).unwrap_or_else(|_| p.clone());
                table.insert("path".into(), abs.display().to_string().into());
            }
        }
        (None, Some(p)) => {
            let (k, abs) = registry.source_for_data(p).map_err(core)?;
            table.insert("kind".into(), k.into());
            table.insert("path".into(), abs.display().to_string().into());
        }
        (None, None) => {
            return Err(DataError::new_err(
                "open: give a path to read, or kind= (e.g. kind=\"sim\")",
            ))
        }
    }
    let mut raw = RawConfig::builtin();
    raw.origin = "keylo.open".into();
    raw.table.insert("source".into(), table.into());
    let config = registry.resolve(&raw).map_err(config)?;
    let source = keylo::build_source(&config, &registry).map_err(core)?;
    Ok(Reader {
        source: Mutex::new(source),
    })
}
