//! Detectors and descriptors written in Python: `keylo.register_detector(name, obj)` makes
//! `kind = "python:NAME"` available to every config built from Python afterwards.

use std::collections::BTreeMap;
use std::sync::Mutex;

use keylo::registry::Factory;
use keylo::{
    BuildContext, CoreError, Descriptor, DescriptorData, Descriptors, Detector, Image, Keypoint,
    Registry,
};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::errors::PluginError;

/// The kind prefix of Python backends.
pub const PREFIX: &str = "python:";

static REGISTERED: Mutex<BTreeMap<String, Py<PyAny>>> = Mutex::new(BTreeMap::new());

/// `keylo.register_detector(name, obj)`: `obj.detect(image)` takes an H×W (or H×W×C) uint8
/// array and returns keypoints N×2 (x, y) up to N×5 (x, y, size, angle, response); with
/// `obj.describe(image, keypoints) -> (keypoints, descriptors)` (uint8 rows: Hamming,
/// float32 rows: L2) the same name is also a descriptor. Configs built afterwards may name
/// `kind = "python:NAME"` in `[detector]` / `[descriptor]`.
#[pyfunction]
pub fn register_detector(name: &str, obj: Bound<'_, PyAny>) -> PyResult<()> {
    if name.is_empty() || name.contains(|c: char| c.is_whitespace() || c == ':') {
        return Err(PluginError::new_err(format!(
            "register_detector: name `{name}` must be non-empty, without spaces or `:`"
        )));
    }
    let any = ["detect", "describe", "downsample"]
        .iter()
        .map(|a| obj.hasattr(*a))
        .collect::<PyResult<Vec<bool>>>()?;
    if !any.contains(&true) {
        return Err(PluginError::new_err(format!(
            "register_detector(`{name}`): the object has neither `detect` nor `describe` \
             (nor `downsample`)"
        )));
    }
    registered()?.insert(name.to_string(), obj.unbind());
    Ok(())
}

fn registered() -> PyResult<std::sync::MutexGuard<'static, BTreeMap<String, Py<PyAny>>>> {
    REGISTERED
        .lock()
        .map_err(|_| PluginError::new_err("the Python detector table failed earlier"))
}

/// keylo's registry plus every Python detector and descriptor registered so far.
pub fn registry(py: Python<'_>) -> PyResult<Registry> {
    let mut registry = keylo::registry();
    for (name, obj) in registered()?.iter() {
        let kind = format!("{PREFIX}{name}");
        let obj = obj.bind(py);
        if obj.hasattr("detect")? {
            registry
                .detectors
                .add_factory(&kind, Box::new(PyFactory::new(name, obj.clone().unbind())));
        }
        if obj.hasattr("describe")? {
            registry
                .descriptors
                .add_factory(&kind, Box::new(PyFactory::new(name, obj.clone().unbind())));
        }
        if obj.hasattr("downsample")? {
            registry
                .downsamplers
                .add_factory(&kind, Box::new(PyFactory::new(name, obj.clone().unbind())));
        }
    }
    Ok(registry)
}

/// Builds [`PyBackend`]s of one Python object.
struct PyFactory {
    name: String,
    summary: String,
    obj: Py<PyAny>,
}

impl PyFactory {
    fn new(name: &str, obj: Py<PyAny>) -> Self {
        Self {
            name: name.to_string(),
            summary: format!("Python object registered as `{name}` (keylo.register_detector)"),
            obj,
        }
    }
}

impl<T: ?Sized> Factory<T> for PyFactory
where
    PyBackend: Into<Box<T>>,
{
    fn summary(&self) -> &str {
        &self.summary
    }

    fn schema(&self) -> serde_json::Value {
        serde_json::json!({ "type": "object", "properties": {}, "additionalProperties": false })
    }

    fn resolve(&self, params: &toml::Table) -> Result<toml::Table, (String, String)> {
        match params.keys().next() {
            None => Ok(toml::Table::new()),
            Some(key) => Err((
                key.clone(),
                format!(
                    "a Python backend (`{}`) takes no config keys: configure the object in Python",
                    self.name
                ),
            )),
        }
    }

    fn build(&self, _params: &toml::Table, _ctx: &BuildContext) -> Result<Box<T>, CoreError> {
        let obj = Python::attach(|py| self.obj.clone_ref(py));
        Ok(PyBackend {
            name: self.name.clone(),
            obj,
        }
        .into())
    }
}

/// A Python detector/descriptor behind keylo's stage traits.
pub struct PyBackend {
    name: String,
    obj: Py<PyAny>,
}

impl From<PyBackend> for Box<dyn Detector> {
    fn from(b: PyBackend) -> Self {
        Box::new(b)
    }
}

impl From<PyBackend> for Box<dyn Descriptor> {
    fn from(b: PyBackend) -> Self {
        Box::new(b)
    }
}

impl PyBackend {
    /// A stage error naming the backend.
    pub(crate) fn error(&self, stage: &str, message: impl std::fmt::Display) -> CoreError {
        CoreError::stage(stage, format!("Python backend `{}`: {message}", self.name))
    }

    /// The Python object.
    pub(crate) fn object<'py>(&self, py: Python<'py>) -> &Bound<'py, PyAny> {
        self.obj.bind(py)
    }

    /// The image as a uint8 array (H×W, or H×W×C), one copy of its rows.
    fn image_array<'py>(&self, py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyAny>> {
        let row = image.width * image.channels;
        let data: Vec<u8> = if image.stride == row {
            image.data[..row * image.height].to_vec()
        } else {
            (0..image.height)
                .flat_map(|y| {
                    image.data[y * image.stride..y * image.stride + row]
                        .iter()
                        .copied()
                })
                .collect()
        };
        let bad = |e: numpy::ndarray::ShapeError| PluginError::new_err(e.to_string());
        if image.channels == 1 {
            let a = Array2::from_shape_vec((image.height, image.width), data).map_err(bad)?;
            Ok(a.into_pyarray(py).into_any())
        } else {
            let shape = (image.height, image.width, image.channels);
            let a = numpy::ndarray::Array3::from_shape_vec(shape, data).map_err(bad)?;
            Ok(a.into_pyarray(py).into_any())
        }
    }

    /// Keypoints from what Python returned: N×2..N×5 numbers, finite, inside the image.
    fn keypoints_of(
        &self,
        stage: &str,
        obj: &Bound<'_, PyAny>,
        image: &Image,
    ) -> Result<Vec<Keypoint>, CoreError> {
        let expected = "an N×2 to N×5 array (x, y[, size, angle, response])";
        // A float32 N×k array is read as it is; anything else goes through numpy.asarray.
        let arr = match obj.extract::<PyReadonlyArray2<f32>>() {
            Ok(a) => a,
            Err(_) => obj
                .py()
                .import("numpy")
                .and_then(|np| np.call_method1("asarray", (obj, "float32")))
                .and_then(|a| a.extract::<PyReadonlyArray2<f32>>())
                .map_err(|_| {
                    self.error(
                        stage,
                        format!("returned {}, expected {expected}", describe(obj)),
                    )
                })?,
        };
        let shape = arr.shape();
        if !(2..=5).contains(&shape[1]) && shape[0] > 0 {
            return Err(self.error(
                stage,
                format!(
                    "returned a {}×{} array, expected {expected}",
                    shape[0], shape[1]
                ),
            ));
        }
        let a = arr.as_array();
        let (w, h) = (image.width as f32, image.height as f32);
        let mut out = Vec::with_capacity(shape[0]);
        for i in 0..shape[0] {
            let get = |k: usize, default: f32| if k < shape[1] { a[(i, k)] } else { default };
            let kp = Keypoint {
                x: get(0, 0.0),
                y: get(1, 0.0),
                size: get(2, 7.0),
                angle: get(3, -1.0),
                response: get(4, 0.0),
                ..Keypoint::default()
            };
            let inside = kp.x.is_finite() && kp.y.is_finite() && kp.x >= 0.0 && kp.y >= 0.0;
            if !inside || kp.x >= w || kp.y >= h {
                return Err(self.error(
                    stage,
                    format!(
                        "keypoint {i} at ({}, {}) lies outside the {}x{} image `{}`",
                        kp.x,
                        kp.y,
                        image.width,
                        image.height,
                        image.name()
                    ),
                ));
            }
            out.push(kp);
        }
        Ok(out)
    }
}

fn describe(obj: &Bound<'_, PyAny>) -> String {
    match obj.getattr("shape") {
        Ok(shape) => format!("an array of shape {shape}"),
        Err(_) => obj
            .get_type()
            .name()
            .map_or_else(|_| "an object".into(), |n| format!("a {n}")),
    }
}

impl Detector for PyBackend {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        Python::attach(|py| {
            let arr = self
                .image_array(py, image)
                .map_err(|e| self.error("detector", e))?;
            let out = self
                .obj
                .bind(py)
                .call_method1("detect", (arr,))
                .map_err(|e| self.error("detector", format!("detect raised {e}")))?;
            self.keypoints_of("detector", &out, image)
        })
    }
}

impl Descriptor for PyBackend {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        Python::attach(|py| {
            let arr = self
                .image_array(py, image)
                .map_err(|e| self.error("descriptor", e))?;
            let kp = Array2::from_shape_fn((keypoints.len(), 5), |(i, k)| {
                let p = &keypoints[i];
                [p.x, p.y, p.size, p.angle, p.response][k]
            });
            let out = self
                .obj
                .bind(py)
                .call_method1("describe", (arr, kp.into_pyarray(py)))
                .map_err(|e| self.error("descriptor", format!("describe raised {e}")))?;
            let pair = out
                .cast::<PyTuple>()
                .ok()
                .filter(|t| t.len() == 2)
                .ok_or_else(|| {
                    self.error(
                        "descriptor",
                        format!(
                            "describe returned {}, expected (keypoints, descriptors)",
                            describe(&out)
                        ),
                    )
                })?;
            let kept = self.keypoints_of(
                "descriptor",
                &pair.get_item(0).map_err(|e| self.error("descriptor", e))?,
                image,
            )?;
            let d = self.descriptors_of(
                &pair.get_item(1).map_err(|e| self.error("descriptor", e))?,
                kept.len(),
            )?;
            *keypoints = kept;
            Ok(d)
        })
    }
}

impl PyBackend {
    /// Descriptor rows: uint8 (binary) or float32 (L2), one per keypoint kept.
    fn descriptors_of(
        &self,
        obj: &Bound<'_, PyAny>,
        rows: usize,
    ) -> Result<Descriptors, CoreError> {
        let bad = |what: String| self.error("descriptor", what);
        let dtype: String = obj
            .getattr("dtype")
            .and_then(|d| d.str())
            .map(|s| s.to_string())
            .map_err(|_| {
                bad(format!(
                    "descriptors are {}, expected a uint8 or float32 N×D array",
                    describe(obj)
                ))
            })?;
        let data = match dtype.as_str() {
            "uint8" => obj.extract::<PyReadonlyArray2<u8>>().map(|a| {
                (
                    a.shape()[0],
                    a.shape()[1],
                    DescriptorData::Binary(a.as_array().iter().copied().collect()),
                )
            }),
            "float32" => obj.extract::<PyReadonlyArray2<f32>>().map(|a| {
                (
                    a.shape()[0],
                    a.shape()[1],
                    DescriptorData::Float(a.as_array().iter().copied().collect()),
                )
            }),
            other => {
                return Err(bad(format!(
                    "descriptors of dtype {other}, expected uint8 or float32"
                )))
            }
        };
        let (n, dim, data) = data.map_err(|_| {
            bad(format!(
                "descriptors are {}, expected an N×D array",
                describe(obj)
            ))
        })?;
        if n != rows {
            return Err(bad(format!("{n} descriptor rows for {rows} keypoints")));
        }
        Ok(Descriptors { rows: n, dim, data })
    }
}
