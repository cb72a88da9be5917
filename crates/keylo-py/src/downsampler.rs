//! A downsampler written in Python: an object registered with `keylo.register_downsampler`
//! (or `register_detector`) that has `downsample(frame, keypoints) -> points` is
//! `kind = "python:NAME"` in `[downsampler]`.

use keylo::{CoreError, Downsampler, FrameFeatures, LidarFrame, PointCloud};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::detectors::PyBackend;
use crate::frames::Frame;

impl From<PyBackend> for Box<dyn Downsampler> {
    fn from(b: PyBackend) -> Self {
        Box::new(b)
    }
}

impl Downsampler for PyBackend {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        Python::attach(|py| {
            let fail = |m: String| self.error("downsampler", m);
            // The frame as keylo.Frame (a copy: the object may outlive the call).
            let f = Py::new(
                py,
                Frame {
                    inner: frame.clone(),
                },
            )
            .map_err(|e| fail(e.to_string()))?;
            let images = PyList::empty(py);
            for c in &features.per_image {
                let d = PyDict::new(py);
                let kp = &c.keypoints;
                let xy = Array2::from_shape_fn((kp.len(), 2), |(i, k)| [kp[i].x, kp[i].y][k]);
                let set = |k: &str, v: Bound<'_, PyAny>| d.set_item(k, v);
                set(
                    "image",
                    c.image
                        .name()
                        .into_pyobject(py)
                        .map_err(|e| fail(e.to_string()))?
                        .into_any(),
                )
                .and_then(|()| set("xy", xy.into_pyarray(py).into_any()))
                .and_then(|()| {
                    set(
                        "scale",
                        (c.image.scale_x, c.image.scale_y)
                            .into_pyobject(py)?
                            .into_any(),
                    )
                })
                .and_then(|()| images.append(d))
                .map_err(|e| fail(e.to_string()))?;
            }
            let out = self
                .object(py)
                .call_method1("downsample", (f, images))
                .map_err(|e| fail(format!("downsample raised {e}")))?;
            let np = py.import("numpy").map_err(|e| fail(e.to_string()))?;
            let arr: PyReadonlyArray2<f64> = np
                .call_method1("asarray", (&out, "float64"))
                .and_then(|a| a.extract::<PyReadonlyArray2<f64>>())
                .map_err(|_| fail("downsample returned something that is not an N×3 or N×4 array (x, y, z[, time])".into()))?;
            let shape = arr.shape();
            if shape[1] != 3 && shape[1] != 4 {
                return Err(fail(format!(
                    "downsample returned a {}×{} array, expected N×3 (x, y, z) or N×4 (with the time relative to the frame)",
                    shape[0], shape[1]
                )));
            }
            let a = arr.as_array();
            let cloud = PointCloud {
                timestamp: frame.timestamp,
                points: (0..shape[0])
                    .map(|i| nalgebra::Point3::new(a[(i, 0)], a[(i, 1)], a[(i, 2)]))
                    .collect(),
                times: (shape[1] == 4).then(|| (0..shape[0]).map(|i| a[(i, 3)]).collect()),
                intensities: None,
            };
            if let Some(i) = cloud
                .points
                .iter()
                .position(|p| !p.coords.iter().all(|v| v.is_finite()))
            {
                return Err(fail(format!(
                    "point {i} of the returned cloud is not finite"
                )));
            }
            Ok(cloud)
        })
    }
}
