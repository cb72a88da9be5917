//! The `sim` source backend: a [`Simulator`] behind [`keylo_core::ImageSource`].

use keylo_core::{
    BuildContext, ConfigError, CoreError, ImageSource, LidarFrame, Registry, SourceInfo, Trajectory,
};

use crate::{SimConfig, SimError, Simulator};

/// One-line summary shown by `keylo config` and the docs.
const SUMMARY: &str =
    "Simulated Ouster-like LiDAR (OS0-128/OS1-64) in a lab, corridor, road or park scene, with ground truth";

impl From<SimError> for CoreError {
    fn from(e: SimError) -> Self {
        match e {
            SimError::InvalidConfig { field, message } => CoreError::Config(ConfigError::Invalid {
                origin: "source (kind = \"sim\")".into(),
                path: format!("source.{field}"),
                message,
            }),
            SimError::Scene { .. } => CoreError::stage("source", e.to_string()),
        }
    }
}

/// Yields the simulator's frames `0..frames` in order.
#[derive(Debug)]
pub struct SimSource {
    sim: Simulator,
    next: usize,
}

impl SimSource {
    /// A source over a new [`Simulator`] for `config`.
    pub fn new(config: &SimConfig) -> Result<Self, SimError> {
        Ok(Self {
            sim: Simulator::new(config)?,
            next: 0,
        })
    }

    /// The simulator behind the source.
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }
}

impl ImageSource for SimSource {
    fn info(&self) -> SourceInfo {
        let c = self.sim.config();
        let s = self.sim.sensor();
        SourceInfo {
            description: format!(
                "sim: scene {}, {}×{}, seed {}, {} frames",
                c.scene.name(),
                s.model,
                s.cols,
                c.seed,
                c.frames
            ),
            frames: Some(self.sim.len()),
        }
    }

    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
        if self.next >= self.sim.len() {
            return None;
        }
        let frame = self.sim.frame(self.next);
        self.next += 1;
        Some(Ok(frame))
    }

    fn ground_truth(&self) -> Option<Trajectory> {
        Some(self.sim.ground_truth())
    }
}

fn build(config: SimConfig, _ctx: &BuildContext) -> Result<Box<dyn ImageSource>, CoreError> {
    Ok(Box::new(SimSource::new(&config)?))
}

/// Registers the source kind `"sim"` (parameters: [`SimConfig`]).
pub fn register(registry: &mut Registry) {
    registry.sources.add::<SimConfig>("sim", SUMMARY, build);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn registered_kind_builds_and_yields_frames() {
        let mut r = Registry::default();
        register(&mut r);
        assert!(r.sources.kinds().contains(&"sim"));
        let f = r.sources.get("sim").unwrap();
        let schema = f.schema().to_string();
        assert!(
            schema.contains("speed_scale") && schema.contains("os1-64"),
            "{schema}"
        );
        let p = f
            .resolve(&table("frames = 2\ncolumns = 512\nsensor = \"os1-64\""))
            .unwrap();
        assert_eq!(p.get("seed").and_then(|v| v.as_integer()), Some(0));
        let mut src = f.build(&p, &BuildContext::default()).unwrap();
        assert_eq!(src.info().frames, Some(2));
        let a = src.next_frame().unwrap().unwrap();
        assert_eq!((a.rows, a.cols), (64, 512));
        assert!(a.check_shape().is_ok());
        assert_eq!(src.next_frame().unwrap().unwrap().index, 1);
        assert!(src.next_frame().is_none());
        assert_eq!(src.ground_truth().unwrap().len(), 2);
    }

    #[test]
    fn bad_params_name_the_field() {
        let mut r = Registry::default();
        register(&mut r);
        let f = r.sources.get("sim").unwrap();
        let err = f.resolve(&table("colums = 3")).unwrap_err();
        assert!(err.1.contains("colums"), "{err:?}");
        let err = f.build(&table("columns = 1000"), &BuildContext::default());
        let msg = err.err().unwrap().to_string();
        assert!(
            msg.contains("source.columns") && msg.contains("512"),
            "{msg}"
        );
    }
}
