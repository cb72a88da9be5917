//! `keylo.Odometry`: the pipeline of a config, fed frame by frame from Python.

use std::sync::Mutex;

use keylo::io::cloud::RawCloud;
use keylo::{Frontend, Pose};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{matrix_f64, points, pose_stack, vector_f64};
use crate::config::{raw_config, table_of};
use crate::errors::{frontend, DataError, StageError};
use crate::frames::Frame;
use crate::result::FrameResult;

struct State {
    frontend: Frontend,
    /// The backend of each stage, `(section, kind)`, defaults filled in.
    kinds: Vec<(String, String)>,
    stamps: Vec<f64>,
    poses: Vec<Pose>,
}

/// The per-frame stages of a config (a TOML path, TOML text or a dict; None: the defaults),
/// fed by `process` (point arrays) or `process_frame` (frames of `keylo.open`). The work runs
/// without the GIL.
#[pyclass(module = "keylo")]
pub struct Odometry {
    state: Mutex<State>,
}

impl Odometry {
    fn state(&self) -> PyResult<std::sync::MutexGuard<'_, State>> {
        self.state
            .lock()
            .map_err(|_| StageError::new_err("the pipeline failed earlier (a panic)"))
    }
}

/// Runs `f` on the frontend without the GIL and records the pose.
fn step(
    py: Python<'_>,
    state: &mut State,
    f: impl FnOnce(&mut Frontend) -> Result<keylo::FrameOutput, keylo::Error> + Send,
) -> PyResult<FrameResult> {
    let fe = &mut state.frontend;
    let out = py.detach(move || f(fe)).map_err(frontend)?;
    state.stamps.push(out.result.stamp);
    state.poses.push(out.result.pose);
    Ok(FrameResult::new(out))
}

/// A 4×4 rigid transform from Python as a pose.
fn pose_arg(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Pose> {
    let m = matrix_f64(obj, what, &[4])?;
    if m.nrows() != 4 {
        return Err(DataError::new_err(format!(
            "{what}: expected a 4×4 matrix, got {}×4",
            m.nrows()
        )));
    }
    let flat: [f64; 16] = std::array::from_fn(|i| m[(i / 4, i % 4)]);
    keylo::rigid::pose_from_matrix(&flat)
        .map_err(|e| DataError::new_err(format!("{what}: not a rigid transform ({e})")))
}

#[pymethods]
impl Odometry {
    #[new]
    #[pyo3(signature = (config=None, *, trust_plugins=false))]
    fn new(
        py: Python<'_>,
        config: Option<&Bound<'_, PyAny>>,
        trust_plugins: bool,
    ) -> PyResult<Self> {
        let raw = raw_config(config)?;
        // A kind that is not a string is never seen: building the frontend below refuses it.
        let kinds = keylo::config::STAGE_DEFAULT_KINDS
            .iter()
            .filter(|(section, _)| *section != "source")
            .map(|(section, _)| {
                let kind = raw
                    .table
                    .get(*section)
                    .and_then(|s| s.get("kind"))
                    .and_then(|k| k.as_str())
                    .unwrap_or(keylo::config::default_kind(section));
                (section.to_string(), kind.to_string())
            })
            .collect();
        let registry = crate::detectors::registry(py)?;
        // A config's own libraries (`[plugins] dirs`, `onnxruntime`) load only when trusted.
        let trust = keylo::config::Trust::opted_in(trust_plugins);
        let frontend = Frontend::from_raw_with(raw, registry, trust).map_err(frontend)?;
        Ok(Self {
            state: Mutex::new(State {
                frontend,
                kinds,
                stamps: Vec::new(),
                poses: Vec::new(),
            }),
        })
    }

    /// Registers one unorganised scan: `points` N×3 (x, y, z) or N×4 (with intensity),
    /// sensor frame, metres; `times` (N, seconds relative to `stamp`) for deskewing; `stamp`
    /// the scan's time (default: the previous stamp + 0.1 s, 0 for the first). Non-finite
    /// points are dropped, as every keylo reader drops them.
    #[pyo3(signature = (points, times=None, stamp=None))]
    fn process(
        &self,
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        times: Option<&Bound<'_, PyAny>>,
        stamp: Option<f64>,
    ) -> PyResult<FrameResult> {
        let m = matrix_f64(points, "points", &[3, 4])?;
        let n = m.nrows();
        let times = times.map(|t| vector_f64(t, "times", n)).transpose()?;
        let mut state = self.state()?;
        let stamp = stamp.unwrap_or_else(|| state.stamps.last().map_or(0.0, |s| s + 0.1));
        let cloud = RawCloud {
            timestamp: stamp,
            points: (0..n)
                .map(|i| [m[(i, 0)] as f32, m[(i, 1)] as f32, m[(i, 2)] as f32])
                .collect(),
            intensity: (m.ncols() == 4).then(|| (0..n).map(|i| m[(i, 3)] as f32).collect()),
            time: times,
            ..RawCloud::default()
        };
        step(py, &mut state, move |fe| fe.push_cloud(&cloud).cloned())
    }

    /// Registers an organised frame (from `keylo.open` or `keylo.sim`).
    fn process_frame(&self, py: Python<'_>, frame: PyRef<'_, Frame>) -> PyResult<FrameResult> {
        let mut state = self.state()?;
        let f = &frame.inner;
        step(py, &mut state, move |fe| fe.push_frame(f).cloned())
    }

    /// The backend of every stage, `{"registrar": "kiss-icp", "downsampler": …}`, the
    /// defaults filled in for sections the config leaves out.
    #[getter]
    fn kinds(&self) -> PyResult<std::collections::BTreeMap<String, String>> {
        Ok(self.state()?.kinds.iter().cloned().collect())
    }

    /// Frames registered since the start or the last `reset`.
    #[getter]
    fn frames(&self) -> PyResult<usize> {
        Ok(self.state()?.poses.len())
    }

    /// Every pose so far, an N×4×4 float64 array (world = first frame).
    #[getter]
    fn trajectory<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        Ok(pose_stack(py, &self.state()?.poses))
    }

    /// The stamp of every pose, seconds (N float64).
    #[getter]
    fn stamps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(self.state()?.stamps.clone().into_pyarray(py))
    }

    /// The registrar's local map in the world frame (M×3 float64).
    fn local_map<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Ok(points(py, &self.state()?.frontend.local_map()))
    }

    /// SLAM hook: the motion from the last frame to the next (4×4 rigid, e.g. from an IMU)
    /// replaces the registrar's constant-velocity guess for the next frame.
    fn set_motion_prior(&self, delta: &Bound<'_, PyAny>) -> PyResult<()> {
        let delta = pose_arg(delta, "motion prior")?;
        self.state()?
            .frontend
            .set_motion_prior(&delta)
            .map_err(frontend)
    }

    /// SLAM hook: the last frame's pose becomes `pose` (4×4 rigid); map and motion kept.
    fn set_pose(&self, pose: &Bound<'_, PyAny>) -> PyResult<()> {
        let pose = pose_arg(pose, "pose")?;
        let mut state = self.state()?;
        state.frontend.set_pose(&pose).map_err(frontend)?;
        if let Some(last) = state.poses.last_mut() {
            *last = pose;
        }
        Ok(())
    }

    /// Saves a global map of the frames processed from now on in the folder `dir`
    /// (docs/maps.md): the world-frame cloud, voxelised (map.ply, map.pcd), and keyframes
    /// with their clouds, keypoints and descriptors. `settings`: a dict of `[map]` keys
    /// (e.g. `{"voxel_size": 0.1}`); None: the defaults. `finish_map()` completes it.
    #[pyo3(signature = (dir, settings=None))]
    fn save_map(
        &self,
        dir: std::path::PathBuf,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let table = match settings {
            Some(d) => table_of(d, "")?,
            None => toml::Table::new(),
        };
        let settings = keylo::map::MapConfig::from_table(&table, "save_map(settings)")
            .map_err(|e| frontend(e.into()))?;
        self.state()?
            .frontend
            .save_map(dir, settings)
            .map_err(frontend)
    }

    /// Completes the map `save_map` started (writes its cloud and map.json) and returns
    /// map.json's contents as a dict; None when no map was being saved.
    fn finish_map<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let manifest = self.state()?.frontend.finish_map().map_err(frontend)?;
        let Some(m) = manifest else {
            return Ok(None);
        };
        let json = serde_json::to_string(&m).map_err(|e| DataError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (json,)).map(Some)
    }

    /// SLAM hook: start over (map, motion and trajectory forgotten).
    fn reset(&self) -> PyResult<()> {
        let mut state = self.state()?;
        state.frontend.reset().map_err(frontend)?;
        state.stamps.clear();
        state.poses.clear();
        Ok(())
    }
}
