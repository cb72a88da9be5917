//! `keylo.FrameResult`: what one registered frame gives back.

use keylo::{DescriptorData, FrameOutput};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::pose_matrix;

/// The result of one frame: pose, counts, stage timings, degeneracy, keypoints.
#[pyclass(frozen, module = "keylo")]
pub struct FrameResult {
    out: FrameOutput,
}

impl FrameResult {
    pub fn new(out: FrameOutput) -> Self {
        Self { out }
    }
}

#[pymethods]
impl FrameResult {
    /// Index of the frame.
    #[getter]
    fn index(&self) -> u64 {
        self.out.result.index
    }

    /// Time the pose refers to, seconds.
    #[getter]
    fn stamp(&self) -> f64 {
        self.out.result.stamp
    }

    /// The sensor pose in the world (first-frame) frame, a 4×4 float64 array.
    #[getter]
    fn pose<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        pose_matrix(&self.out.result.pose).into_pyarray(py)
    }

    /// Keypoints found over all images.
    #[getter]
    fn keypoint_count(&self) -> usize {
        self.out.result.keypoints
    }

    /// Points the downsampler handed to the registrar.
    #[getter]
    fn cloud_points(&self) -> usize {
        self.out.result.cloud_points
    }

    /// Points the registrar aligned after its own preprocessing (0: the pose was predicted).
    #[getter]
    fn registered_points(&self) -> usize {
        self.out.result.registered_points
    }

    /// Why the registration could not constrain the pose, or None: a dict with `reason`
    /// (`too-few-points`: `points` below the registrar's `minimum`; `no-information`:
    /// `directions` of the six without information). The pose is then (partly) predicted.
    #[getter]
    fn degenerate<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(d) = self.out.result.degenerate else {
            return Ok(None);
        };
        let dict = PyDict::new(py);
        dict.set_item("reason", d.label())?;
        match d {
            keylo::Degenerate::TooFewPoints { points, minimum } => {
                dict.set_item("points", points)?;
                dict.set_item("minimum", minimum)?;
            }
            keylo::Degenerate::NoInformation { directions } => {
                dict.set_item("directions", directions)?;
            }
        }
        Ok(Some(dict))
    }

    /// Points in the local map after the frame.
    #[getter]
    fn map_points(&self) -> usize {
        self.out.result.map_points
    }

    /// Solver iterations.
    #[getter]
    fn iterations(&self) -> usize {
        self.out.result.iterations
    }

    /// Whether the solver converged.
    #[getter]
    fn converged(&self) -> bool {
        self.out.result.converged
    }

    /// Localisation in a prior map (`[registrar] kind = "localise"`): the share of the
    /// registered points with a map point within the fitness distance; None for odometry.
    #[getter]
    fn fitness(&self) -> Option<f64> {
        self.out.result.fit.map(|f| f.fitness)
    }

    /// Localisation: whether the fitness reached its threshold (False: the pose is not to be
    /// trusted); None for odometry.
    #[getter]
    fn tracking(&self) -> Option<bool> {
        self.out.result.fit.map(|f| f.tracking)
    }

    /// Seconds per stage: `image`, `detect`, `describe`, `downsample`, `register`, `total`.
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = &self.out.result.timings;
        let d = PyDict::new(py);
        d.set_item("image", t.image)?;
        d.set_item("detect", t.detect)?;
        d.set_item("describe", t.describe)?;
        d.set_item("downsample", t.downsample)?;
        d.set_item("register", t.register)?;
        d.set_item("total", t.total())?;
        Ok(d)
    }

    /// The registrar's degeneracy analysis (`eigenvalues`, `eigenvectors` 6×6 rows,
    /// `condition`, `weak`, `length_scale`, `residuals`), or None.
    #[getter]
    fn degeneracy<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(g) = self.out.degeneracy() else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("eigenvalues", g.eigenvalues.to_vec().into_pyarray(py))?;
        let vectors = Array2::from_shape_fn((6, 6), |(r, c)| g.eigenvectors[r][c]);
        d.set_item("eigenvectors", vectors.into_pyarray(py))?;
        d.set_item("condition", g.condition)?;
        d.set_item("weak", g.weak)?;
        d.set_item("length_scale", g.length_scale)?;
        d.set_item("residuals", g.residuals)?;
        Ok(Some(d))
    }

    /// The 6×6 pose covariance `sigma² H⁻¹` (twist `[tx, ty, tz, rx, ry, rz]`) for residual
    /// noise `sigma` metres; None without an analysis or with an unconstrained direction.
    fn covariance<'py>(
        &self,
        py: Python<'py>,
        sigma: f64,
    ) -> Option<Bound<'py, numpy::PyArray2<f64>>> {
        let c = self.out.covariance(sigma)?;
        Some(Array2::from_shape_fn((6, 6), |(r, k)| c[r][k]).into_pyarray(py))
    }

    /// The 6×6 pose covariance under the noise model fitted for the registrar (twist
    /// `[tx, ty, tz, rx, ry, rz]`, world frame): what keylo's pose graph and ROS 2 node use
    /// (docs/maps.md); None without an analysis.
    #[getter]
    fn fitted_covariance<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray2<f64>>> {
        let c = self.out.fitted_covariance?;
        Some(Array2::from_shape_fn((6, 6), |(r, k)| c[r][k]).into_pyarray(py))
    }

    /// Per image: `image` (name), `xy` (N×2 float32), `size`, `angle`, `response` (N),
    /// `points` (N×3 float64 sensor-frame point under each keypoint, NaN over no return) and
    /// `descriptors` (N×D uint8 or float32, or None).
    #[getter]
    fn keypoints<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for (c, points) in self
            .out
            .features
            .per_image
            .iter()
            .zip(&self.out.keypoint_points)
        {
            let d = PyDict::new(py);
            let kp = &c.keypoints;
            d.set_item("image", c.image.name())?;
            let xy = Array2::from_shape_fn((kp.len(), 2), |(i, k)| [kp[i].x, kp[i].y][k]);
            d.set_item("xy", xy.into_pyarray(py))?;
            let col = |f: fn(&keylo::Keypoint) -> f32| kp.iter().map(f).collect::<Vec<f32>>();
            d.set_item("size", col(|k| k.size).into_pyarray(py))?;
            d.set_item("angle", col(|k| k.angle).into_pyarray(py))?;
            d.set_item("response", col(|k| k.response).into_pyarray(py))?;
            let p = Array2::from_shape_fn((points.len(), 3), |(i, k)| {
                points[i].map_or(f64::NAN, |p| p[k])
            });
            d.set_item("points", p.into_pyarray(py))?;
            match &c.descriptors {
                Some(desc) => match &desc.data {
                    DescriptorData::Binary(v) => {
                        let a = Array2::from_shape_vec((desc.rows, desc.dim), v.clone())
                            .unwrap_or_else(|_| Array2::zeros((0, desc.dim)));
                        d.set_item("descriptors", a.into_pyarray(py))?
                    }
                    DescriptorData::Float(v) => {
                        let a = Array2::from_shape_vec((desc.rows, desc.dim), v.clone())
                            .unwrap_or_else(|_| Array2::zeros((0, desc.dim)));
                        d.set_item("descriptors", a.into_pyarray(py))?
                    }
                },
                None => d.set_item("descriptors", py.None())?,
            }
            list.append(d)?;
        }
        Ok(list)
    }

    fn __repr__(&self) -> String {
        let t = self.out.result.pose.translation.vector;
        format!(
            "FrameResult(index={}, stamp={:.6}, xyz=({:.3}, {:.3}, {:.3}), cloud_points={}, converged={})",
            self.out.result.index,
            self.out.result.stamp,
            t.x,
            t.y,
            t.z,
            self.out.result.cloud_points,
            if self.out.result.converged { "True" } else { "False" }
        )
    }
}
