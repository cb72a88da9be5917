//! `--view` and `--record`: a run streamed live to Foxglove or Lichtblick and recorded as MCAP
//! (crate keylo-view, cargo feature `view`). Without the feature the options are refused with a
//! message saying how to build it.

use anyhow::Result;
use keylo::{FrameFeatures, FrameResult, LidarFrame, Odometry, PointCloud, Trajectory};
use nalgebra::Point3;

use crate::arg_groups::ViewArgs;

/// What the recording and the viewer are told about the run (read only with the `view`
/// feature: without it the options are refused before a run starts).
#[cfg_attr(not(feature = "view"), allow(dead_code))]
pub struct RunDescription {
    pub command: String,
    pub config_origin: String,
    pub config_toml: String,
    pub source: String,
    /// The images the pipeline makes (advertised before the first frame).
    pub images: Vec<String>,
    /// The reference trajectory to draw beside the estimate.
    pub reference: Option<Trajectory>,
    /// The frame of the poses and the map (`odom`; `map` when localising in a saved map).
    pub world_frame: &'static str,
    /// The map does not change (localising in a saved one): recorded once.
    pub fixed_map: bool,
}

impl RunDescription {
    /// The run of `config` (its resolved text `resolved`) on `source`, by this process's
    /// command line, in the world frame `odom`, with the images `odometry` makes; no reference.
    pub fn of(
        config: &keylo::config::PipelineConfig,
        resolved: String,
        source: String,
        odometry: Option<&Odometry>,
    ) -> Self {
        Self {
            command: std::env::args().collect::<Vec<_>>().join(" "),
            config_origin: config.origin.clone(),
            config_toml: resolved,
            source,
            images: (odometry.and_then(|o| o.image.as_ref()))
                .map_or_else(Vec::new, |b| b.image_names()),
            reference: None,
            world_frame: "odom",
            fixed_map: false,
        }
    }
}

/// A started viewer and/or recording.
#[cfg(feature = "view")]
pub struct Session(keylo_view::Viewer);

/// No viewer in this build: nothing can be started.
#[cfg(not(feature = "view"))]
pub enum Session {}

/// Starts what `args` ask for (`None` when nothing); with `--view-wait`, waits for a viewer.
/// Every option is checked before anything starts (a bad one leaves an existing FILE alone).
#[cfg(feature = "view")]
pub fn start(args: &ViewArgs, run: RunDescription, quiet: bool) -> Result<Option<Session>> {
    let wait_limit = args.view_wait.map(wait_limit).transpose()?;
    if args.view_wait.is_some() && args.view.is_none() {
        tracing::warn!("--view-wait does nothing without --view");
    }
    if args.view.is_none() && args.record.is_none() {
        return Ok(None);
    }
    let mut options = keylo_view::ViewOptions {
        serve: args.view.clone(),
        record: args.record.clone(),
        world_frame: run.world_frame.into(),
        fixed_map: run.fixed_map,
        ..Default::default()
    };
    if let Some(n) = args.view_map_every {
        options.map_every = n;
    }
    if let Some(hz) = args.view_hz {
        anyhow::ensure!(
            hz.is_finite() && hz >= 0.0,
            "--view-hz {hz}: expected a rate ≥ 0 (0: every frame)"
        );
        options.max_hz = hz;
    }
    let info = keylo_view::RunInfo {
        config_toml: Some(run.config_toml),
        config_origin: run.config_origin,
        source: run.source,
        command: run.command,
        images: run.images,
        reference: run.reference,
    };
    let viewer = keylo_view::Viewer::start(&options, &info)?;
    if let Some(url) = viewer.url() {
        if !quiet {
            eprintln!(
                "live view at {url}: in Foxglove or Lichtblick, Open connection → Foxglove \
                 WebSocket → {url}"
            );
        }
        if let Some(limit) = wait_limit {
            eprintln!("waiting for a viewer to connect to {url} (Ctrl-C to stop)…");
            if !viewer.wait_for_client(limit, &|| false) {
                tracing::warn!("no viewer connected to {url} in time: running without one");
            }
        }
    }
    Ok(Some(Session(viewer)))
}

/// `--view-wait`'s limit (`None`: no limit).
#[cfg(feature = "view")]
fn wait_limit(secs: f64) -> Result<Option<std::time::Duration>> {
    match secs {
        s if s.is_infinite() && s > 0.0 => Ok(None),
        s if s.is_finite() && s >= 0.0 => Ok(Some(std::time::Duration::from_secs_f64(s))),
        s => anyhow::bail!("--view-wait {s}: expected seconds ≥ 0 (or no value: no limit)"),
    }
}

#[cfg(not(feature = "view"))]
pub fn start(args: &ViewArgs, _run: RunDescription, _quiet: bool) -> Result<Option<Session>> {
    if args.view.is_some() || args.record.is_some() {
        anyhow::bail!(
            "--view and --record need keylo built with the cargo feature `view` (on by \
             default): cargo build --release -p keylo-cli --features view"
        );
    }
    Ok(None)
}

#[cfg(feature = "view")]
impl Session {
    /// Sends one frame (its cloud and, when due, the local map are taken from `odometry`).
    pub fn frame(
        &mut self,
        odometry: &Odometry,
        frame: &LidarFrame,
        result: &FrameResult,
        features: Option<&FrameFeatures>,
        seconds: f64,
    ) {
        let map = self.0.wants_map().then(|| odometry.local_map());
        let cloud = odometry.last_cloud();
        self.send(frame, result, features, cloud, map.as_deref(), seconds);
    }

    /// Whether the next frame sends a map (only then is it worth fetching).
    pub fn wants_map(&self) -> bool {
        self.0.wants_map()
    }

    /// Sends one frame with its registered cloud (sensor frame) and, when
    /// [`Session::wants_map`] said so, the map (world frame).
    pub fn send(
        &mut self,
        frame: &LidarFrame,
        result: &FrameResult,
        features: Option<&FrameFeatures>,
        cloud: Option<&PointCloud>,
        map: Option<&[Point3<f64>]>,
        seconds: f64,
    ) {
        self.0.frame(&keylo_view::FrameView {
            frame,
            result,
            features,
            cloud,
            map,
            seconds,
        });
    }

    /// Sends the last map, stops the server and closes the recording (saying where it is).
    pub fn finish(self, odometry: &Odometry) -> Result<()> {
        self.finish_with(&odometry.local_map())
    }

    /// [`Session::finish`] with the map given.
    pub fn finish_with(self, map: &[Point3<f64>]) -> Result<()> {
        if let Some(r) = self.0.finish(Some(map))? {
            tracing::info!(
                "recorded {} frames to {} ({:.1} MB)",
                r.frames,
                r.path.display(),
                r.bytes as f64 / 1e6
            );
        }
        Ok(())
    }
}

#[cfg(not(feature = "view"))]
impl Session {
    pub fn frame(
        &mut self,
        _: &Odometry,
        _: &LidarFrame,
        _: &FrameResult,
        _: Option<&FrameFeatures>,
        _: f64,
    ) {
        match *self {}
    }

    pub fn wants_map(&self) -> bool {
        match *self {}
    }

    pub fn send(
        &mut self,
        _: &LidarFrame,
        _: &FrameResult,
        _: Option<&FrameFeatures>,
        _: Option<&PointCloud>,
        _: Option<&[Point3<f64>]>,
        _: f64,
    ) {
        match *self {}
    }

    pub fn finish(self, _: &Odometry) -> Result<()> {
        match self {}
    }

    pub fn finish_with(self, _: &[Point3<f64>]) -> Result<()> {
        match self {}
    }
}
