//! The pipeline behind the C API: the facade's [`keylo::Frontend`] plus the buffers the C
//! API lends out (valid until the next call on the same pipeline).

use keylo::io::cloud::RawCloud;
use keylo::{FrameOutput, Frontend, LidarFrame, Odometry};

use crate::CapiError;

/// A pipeline fed by the caller.
pub struct Embedded {
    frontend: Frontend,
    /// The last frame's registered cloud in the world frame, xyz interleaved.
    world_cloud: Vec<f64>,
    /// The local map as last asked for, xyz interleaved.
    local_map: Vec<f64>,
}

impl Embedded {
    /// A pipeline from TOML `text`; relative paths resolve against `base_dir`; `trust` says
    /// whether the libraries the config names itself may be loaded.
    pub fn new(
        text: &str,
        base_dir: &std::path::Path,
        trust: keylo::config::Trust,
    ) -> Result<Self, CapiError> {
        Ok(Self {
            frontend: Frontend::from_toml_with(text, base_dir, trust)?,
            world_cloud: Vec::new(),
            local_map: Vec::new(),
        })
    }

    /// Processes an organised frame on the projection grid (its `index` and `beams` are
    /// filled in here).
    pub fn push_frame(&mut self, mut frame: LidarFrame) -> Result<(), CapiError> {
        frame.index = self.frontend.frames();
        frame.beams = self.frontend.beams().clone();
        self.frontend.push_frame(&frame)?;
        self.update_world_cloud();
        Ok(())
    }

    /// Projects an unorganised cloud onto the `[source.projection]` grid and processes it.
    pub fn push_points(&mut self, cloud: &RawCloud) -> Result<(), CapiError> {
        self.frontend.push_cloud(cloud)?;
        self.update_world_cloud();
        Ok(())
    }

    fn update_world_cloud(&mut self) {
        self.world_cloud.clear();
        let (Some(cloud), Some(pose)) = (self.frontend.last_cloud(), self.frontend.pose()) else {
            return;
        };
        for p in &cloud.points {
            let w = pose * p;
            self.world_cloud.extend_from_slice(&[w.x, w.y, w.z]);
        }
    }

    /// The per-frame stages, for the SLAM hooks.
    pub fn odometry_mut(&mut self) -> &mut Odometry {
        self.frontend.odometry_mut()
    }

    /// Starts over ([`Frontend::reset`]): the last result and cloud are forgotten too.
    pub fn reset(&mut self) -> Result<(), CapiError> {
        self.frontend.reset()?;
        self.world_cloud.clear();
        Ok(())
    }

    /// Starts saving a global map in `dir` ([`Frontend::save_map`]).
    pub fn save_map(
        &mut self,
        dir: &str,
        settings: keylo::map::MapConfig,
    ) -> Result<(), CapiError> {
        Ok(self.frontend.save_map(dir, settings)?)
    }

    /// Completes the map being saved ([`Frontend::finish_map`]).
    pub fn finish_map(&mut self) -> Result<(), CapiError> {
        self.frontend.finish_map()?;
        Ok(())
    }

    /// Frames registered since the start or the last reset.
    pub fn frames(&self) -> u64 {
        self.frontend.frames()
    }

    /// The output of the last frame pushed.
    pub fn last(&self) -> Option<&FrameOutput> {
        self.frontend.last()
    }

    /// The last frame's registered cloud in the world frame, xyz interleaved.
    pub fn world_cloud(&self) -> &[f64] {
        &self.world_cloud
    }

    /// The registrar's local map in the world frame, xyz interleaved (copied now; kept until
    /// the next call).
    pub fn local_map(&mut self) -> &[f64] {
        self.local_map.clear();
        for p in self.frontend.local_map() {
            self.local_map.extend_from_slice(&[p.x, p.y, p.z]);
        }
        &self.local_map
    }
}
