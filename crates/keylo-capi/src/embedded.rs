//! The pipeline behind the C API, in safe Rust: frames in, poses and clouds out.

use std::sync::Arc;

use keylo::config::RawConfig;
use keylo::io::cloud::{ProjectionConfig, Projector, RawCloud, Sensor};
use keylo::registry::parse_params;
use keylo::{BeamGeometry, FrameResult, LidarFrame, Odometry};

use crate::CapiError;

/// A pipeline fed by the caller. The config's `[source]` is not built: its
/// `[source.projection]` table (if any) says how pushed point clouds become images.
pub struct Embedded {
    odometry: Odometry,
    projector: Projector,
    beams: Arc<BeamGeometry>,
    frames: u64,
    last: Option<FrameResult>,
    /// The last frame's registered cloud in the world frame, xyz interleaved.
    world_cloud: Vec<f64>,
}

impl Embedded {
    /// A pipeline from TOML `text`; relative paths resolve against `base_dir`.
    pub fn new(text: &str, base_dir: &std::path::Path) -> Result<Self, CapiError> {
        let mut raw = RawConfig::parse("keylo_pipeline_new config", text)?;
        raw.base_dir = base_dir.to_path_buf();
        let projection = projection(&raw)?;
        raw.table.remove("source");
        #[allow(unused_mut)] // mutated only with run-time plugins
        let mut registry = keylo::registry();
        #[cfg(feature = "plugins")]
        keylo::plugin::load_for_config(&mut registry, &raw)?;
        let config = registry.resolve(&raw)?;
        let odometry = Odometry::build(&config, &registry)?;
        let mut projector = Projector::from_config(&projection, Sensor::Generic)
            .map_err(|m| CapiError::Argument(format!("[source.projection]: {m}")))?;
        projector.set_grid_needed(odometry.needs_grid());
        let beams = projector.beams().clone();
        Ok(Self {
            odometry,
            projector,
            beams,
            frames: 0,
            last: None,
            world_cloud: Vec::new(),
        })
    }

    /// Processes an organised frame (`index`, `beams` are filled in here).
    pub fn push_frame(&mut self, mut frame: LidarFrame) -> Result<(), CapiError> {
        frame.index = self.frames;
        frame.beams = self.beams.clone();
        self.process(&frame)
    }

    /// Projects an unorganised cloud onto the `[source.projection]` grid and processes it.
    pub fn push_points(&mut self, cloud: &RawCloud) -> Result<(), CapiError> {
        let frame = self
            .projector
            .project(cloud, self.frames)
            .map_err(|m| CapiError::Argument(format!("points: {m}")))?;
        self.process(&frame)
    }

    fn process(&mut self, frame: &LidarFrame) -> Result<(), CapiError> {
        let result = self.odometry.process(frame)?;
        self.frames += 1;
        self.world_cloud.clear();
        if let Some(cloud) = self.odometry.last_cloud() {
            for p in &cloud.points {
                let w = result.pose * p;
                self.world_cloud.extend_from_slice(&[w.x, w.y, w.z]);
            }
        }
        self.last = Some(result);
        Ok(())
    }

    /// The per-frame stages, for the SLAM hooks (`Odometry::set_motion_prior`, `reset`,
    /// `set_pose`, `local_map`).
    pub fn odometry_mut(&mut self) -> &mut Odometry {
        &mut self.odometry
    }

    /// Starts over ([`Odometry::reset`]): the last result and cloud are forgotten too.
    pub fn reset(&mut self) -> Result<(), CapiError> {
        self.odometry.reset()?;
        self.last = None;
        self.world_cloud.clear();
        Ok(())
    }

    /// The result of the last frame pushed.
    pub fn last(&self) -> Option<&FrameResult> {
        self.last.as_ref()
    }

    /// The last frame's registered cloud in the world frame, xyz interleaved.
    pub fn world_cloud(&self) -> &[f64] {
        &self.world_cloud
    }
}

/// `[source.projection]` of `raw`, or the default projection.
fn projection(raw: &RawConfig) -> Result<ProjectionConfig, CapiError> {
    let table = raw
        .table
        .get("source")
        .and_then(|s| s.get("projection"))
        .and_then(toml::Value::as_table);
    match table {
        None => Ok(ProjectionConfig::default()),
        Some(t) => parse_params::<ProjectionConfig>(t).map_err(|(path, message)| {
            CapiError::Argument(format!("[source.projection] `{path}`: {message}"))
        }),
    }
}
