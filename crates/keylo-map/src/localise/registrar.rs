//! `[registrar] kind = "localise"`: the [`Localiser`] as a registrar, so every front end
//! (`keylo run`, `keylo ros2`, Python, the C API) localises in a saved map from a config.
//! Poses are in the map's world frame; each result carries the frame's fit
//! ([`keylo_core::MapFit`]).

use keylo_core::config::StageParams;
use keylo_core::{BuildContext, CoreError, MapFit, PointCloud, Pose, Registrar, Registration};

use super::{initial_pose, pose_of_values, LocaliseConfig, Localiser};
use crate::Map;

keylo_core::stage_params!(LocaliseConfig => "localise" as RegistrarParams);

/// Registers the `localise` registrar.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.registrars.add::<LocaliseConfig>(
        LocaliseConfig::KIND,
        "localisation in a saved map (keylo run --map-out): ICP or NDT against the fixed map, per-frame fitness and tracking",
        |config, ctx| Ok(Box::new(LocaliseRegistrar::open(config, ctx)?)),
    );
}

/// A [`Localiser`] in the map a config names.
pub struct LocaliseRegistrar {
    localiser: Localiser,
    start: Pose,
}

impl LocaliseRegistrar {
    /// Opens `config.map` (relative to the config's folder) and starts at
    /// `config.initial_pose`, else the map's first keyframe; errors name the map and what
    /// is wrong.
    pub fn open(config: LocaliseConfig, ctx: &BuildContext) -> Result<Self, CoreError> {
        let stage = |message: String| CoreError::stage("registrar", message);
        if config.map.trim().is_empty() {
            return Err(stage(
                "localise: `map` is empty; expected the folder of a saved map (keylo run … \
                 --map-out DIR)"
                    .into(),
            ));
        }
        let dir = ctx.resolve_path(&config.map);
        let map = Map::open(&dir).map_err(|e| stage(format!("localise: {e}")))?;
        let given = match config.initial_pose.as_slice() {
            [] => None,
            v => {
                Some(pose_of_values(v).map_err(|e| stage(format!("localise: initial_pose: {e}")))?)
            }
        };
        let start = initial_pose(&map, given).map_err(|e| stage(format!("localise: {e}")))?;
        let points = map.points().map_err(|e| stage(format!("localise: {e}")))?;
        let localiser =
            Localiser::new(&points, start, config).map_err(|e| stage(format!("{e}")))?;
        tracing::info!(
            "localise: map {} ({} points), starting at ({:.2}, {:.2}, {:.2})",
            dir.display(),
            localiser.map_points(),
            start.translation.x,
            start.translation.y,
            start.translation.z
        );
        Ok(Self { localiser, start })
    }
}

impl Registrar for LocaliseRegistrar {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        let l = self.localiser.localise_cloud(cloud);
        let end = cloud
            .times
            .as_ref()
            .and_then(|t| t.iter().copied().reduce(f64::max))
            .unwrap_or(0.0);
        Ok(Registration {
            stamp: cloud.timestamp + end,
            pose: l.pose,
            source_points: l.points,
            iterations: l.iterations,
            converged: l.converged,
            degeneracy: None,
            fit: Some(MapFit {
                fitness: l.fitness,
                tracking: l.tracking,
            }),
        })
    }

    fn map_size(&self) -> usize {
        self.localiser.map_points()
    }

    fn set_motion_prior(&mut self, delta: &Pose) -> Result<(), CoreError> {
        keylo_core::rigid::check_rigid(delta, "motion prior")?;
        self.localiser.set_motion_prior(*delta);
        Ok(())
    }

    /// Back to the initial pose, as a new localiser (the map is fixed and stays).
    fn reset(&mut self) -> Result<(), CoreError> {
        self.localiser.restart(self.start);
        Ok(())
    }

    /// The relocalisation hook: the last frame's pose becomes `pose`; unlike odometry the
    /// motion model is forgotten too (it may have been learnt while lost).
    fn set_pose(&mut self, pose: &Pose) -> Result<(), CoreError> {
        keylo_core::rigid::check_rigid(pose, "pose")?;
        self.localiser.set_pose(*pose);
        Ok(())
    }
}
