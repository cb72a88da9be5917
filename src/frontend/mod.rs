//! [`Frontend`]: keylo as a SLAM front end inside your own loop. Push point clouds (or
//! organised frames) one at a time; read back the pose, the degeneracy and covariance, the
//! keypoints with their descriptors and 3-D points; drive it with the SLAM hooks (motion
//! prior, reset, set pose, local map).
//!
//! ```
//! use keylo::registration::NdtConfig;
//!
//! let mut frontend = keylo::Frontend::builder()
//!     .registrar(&NdtConfig::default())
//!     .build()?;
//! // `scan(x)`: what a LiDAR standing `x` metres along a room with five pillars sees (one
//! // ray per 0.5° of azimuth and 2° of elevation; hidden here, it is plain ray casting).
//! # let scan = |x0: f64| -> Vec<[f64; 3]> {
//! #     // Entry and exit distances along `d` from the sensor through an axis-aligned box.
//! #     let slab = |lo: [f64; 3], hi: [f64; 3], d: [f64; 3]| {
//! #         (0..3).fold((f64::NEG_INFINITY, f64::INFINITY), |(near, far), k| {
//! #             let o = if k == 0 { x0 } else { 0.0 };
//! #             let (a, b) = ((lo[k] - o) / d[k], (hi[k] - o) / d[k]);
//! #             (near.max(a.min(b)), far.min(a.max(b)))
//! #         })
//! #     };
//! #     let pillars = [[2.0, 2.0], [-3.0, -1.5], [4.0, -2.0], [-1.0, 2.5], [5.5, 1.0]];
//! #     let mut points = Vec::new();
//! #     for az in 0..720 {
//! #         for el in -12..=12 {
//! #             let (a, e) = ((f64::from(az) * 0.5).to_radians(), f64::from(2 * el).to_radians());
//! #             let d = [a.cos() * e.cos(), a.sin() * e.cos(), e.sin()];
//! #             let mut t = slab([-6.0, -3.0, -1.5], [7.0, 4.0, 2.5], d).1;
//! #             for [px, py] in pillars {
//! #                 let (near, far) = slab([px - 0.3, py - 0.3, -1.5], [px + 0.3, py + 0.3, 2.5], d);
//! #                 if near > 0.0 && near <= far {
//! #                     t = t.min(near);
//! #                 }
//! #             }
//! #             points.push([t * d[0], t * d[1], t * d[2]]);
//! #         }
//! #     }
//! #     points
//! # };
//! // Ten scans 0.1 s apart, moving 0.2 m along x each.
//! for k in 0..10 {
//!     let out = frontend.push_points(0.1 * k as f64, &scan(0.2 * k as f64), None)?;
//!     println!("frame {k}: x = {:.3} m", out.pose().translation.x);
//! }
//! let x = frontend.pose().unwrap().translation.x;
//! assert!((x - 1.8).abs() < 0.05, "{x}");
//! assert!(!frontend.local_map().is_empty());
//! # Ok::<(), keylo::Error>(())
//! ```

mod builder;
mod error;
mod output;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use keylo_core::config::{RawConfig, Trust};
use keylo_core::registry::parse_params;
use keylo_core::{BeamGeometry, LidarFrame, Odometry, Pose, Registry};
use keylo_io::cloud::{ProjectionConfig, Projector, RawCloud, Sensor};
use keylo_map::covariance::{array, frame_covariance, matrix, NoiseModel, PLAIN_SIGMA_M};
use keylo_map::{MapBuilder, MapConfig, MapManifest};
use nalgebra::Point3;

pub use builder::FrontendBuilder;
pub use error::Error;
pub use output::{DescriptorRow, FrameOutput, KeypointView};

/// The per-frame stages of a pipeline fed by the caller. Not `Sync`: use it from one thread at
/// a time (it is `Send`: move it where you like); see [`Odometry`].
pub struct Frontend {
    odometry: Odometry,
    projector: Projector,
    frames: u64,
    last: Option<FrameOutput>,
    /// The global map being saved, if [`Frontend::save_map`] started one.
    map: Option<MapBuilder>,
    /// How a frame's `H⁻¹` becomes [`FrameOutput::fitted_covariance`].
    noise: NoiseModel,
}

impl Frontend {
    /// A frontend from typed configs or your own stage instances.
    pub fn builder() -> FrontendBuilder {
        FrontendBuilder::new()
    }

    /// A frontend from TOML text (a keylo config file's content); relative paths resolve
    /// against `base_dir`. `[source]` is not built: its `[source.projection]` table (if any)
    /// says how pushed point clouds become frames. A config naming libraries of its own
    /// (`[plugins] dirs`, `onnxruntime`) is refused: see [`Frontend::from_toml_with`].
    pub fn from_toml(text: &str, base_dir: impl Into<PathBuf>) -> Result<Self, Error> {
        Self::from_toml_with(text, base_dir, Trust::Installed)
    }

    /// [`Frontend::from_toml`] under `trust`: [`Trust::Config`] also loads the plugin
    /// libraries found in the config's own `[plugins] dirs` and its `onnxruntime` paths,
    /// whose load-time code then runs (docs/plugins.md, "Trust").
    pub fn from_toml_with(
        text: &str,
        base_dir: impl Into<PathBuf>,
        trust: Trust,
    ) -> Result<Self, Error> {
        let mut raw = RawConfig::parse("embedded config", text)?;
        raw.base_dir = base_dir.into();
        Self::from_raw_with(raw, crate::registry(), trust)
    }

    /// A frontend from a parsed config and the registry that resolves its kinds; a config
    /// naming libraries of its own is refused (see [`Frontend::from_raw_with`]).
    pub fn from_raw(raw: RawConfig, registry: Registry) -> Result<Self, Error> {
        Self::from_raw_with(raw, registry, Trust::Installed)
    }

    /// [`Frontend::from_raw`] under `trust` (see [`Frontend::from_toml_with`]).
    pub fn from_raw_with(raw: RawConfig, registry: Registry, trust: Trust) -> Result<Self, Error> {
        let projection = projection_of(&raw)?;
        let odometry = odometry_of(&raw, registry, trust)?;
        let mut frontend = Self::with_odometry(odometry, &projection)?;
        frontend.set_noise_model(noise_of(&raw));
        Ok(frontend)
    }

    /// How [`FrameOutput::fitted_covariance`] is made: by default the model fitted for the
    /// config's registrar (`NoiseModel::fitted`), plain `σ² H⁻¹` with σ = 0.03 m for others
    /// and for stages built by hand.
    pub fn set_noise_model(&mut self, noise: NoiseModel) {
        self.noise = noise;
    }

    /// A frontend around stages you built (or changed) yourself.
    pub fn with_odometry(odometry: Odometry, projection: &ProjectionConfig) -> Result<Self, Error> {
        let mut projector =
            Projector::from_config(projection, Sensor::Generic).map_err(Error::Projection)?;
        projector.set_grid_needed(odometry.needs_grid());
        Ok(Self {
            odometry,
            projector,
            frames: 0,
            last: None,
            map: None,
            noise: NoiseModel::plain(PLAIN_SIGMA_M),
        })
    }

    /// Registers one scan: `points` in the sensor frame (metres), taken at `stamp` seconds,
    /// with each point's time relative to `stamp` when known (for deskewing), as KISS-ICP's
    /// `RegisterFrame(points, timestamps)`. Points with a non-finite coordinate or time are
    /// dropped, as every keylo reader drops them. Coordinates are stored as `f32` (as every
    /// LiDAR driver delivers them).
    pub fn push_points(
        &mut self,
        stamp: f64,
        points: &[[f64; 3]],
        times: Option<&[f64]>,
    ) -> Result<&FrameOutput, Error> {
        if let Some(t) = times.filter(|t| t.len() != points.len()) {
            return Err(Error::TimesLength {
                frame: self.frames,
                times: t.len(),
                points: points.len(),
            });
        }
        let cloud = RawCloud {
            timestamp: stamp,
            points: points
                .iter()
                .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32])
                .collect(),
            time: times.map(<[f64]>::to_vec),
            ..RawCloud::default()
        };
        self.push_cloud(&cloud)
    }

    /// Registers one cloud with any of its fields (intensity, ring, per-point time, an
    /// organised grid): projected onto the `[source.projection]` grid, every point kept.
    pub fn push_cloud(&mut self, cloud: &RawCloud) -> Result<&FrameOutput, Error> {
        let frame = self
            .projector
            .project(cloud, self.frames)
            .map_err(|source| Error::Points {
                frame: self.frames,
                source,
            })?;
        self.process(&frame)
    }

    /// Registers an organised frame (e.g. from [`keylo_io::ouster`]'s reader or your own
    /// driver), as it is.
    pub fn push_frame(&mut self, frame: &LidarFrame) -> Result<&FrameOutput, Error> {
        self.process(frame)
    }

    /// The beam geometry of the projection grid (for organised frames you build yourself
    /// on that grid).
    pub fn beams(&self) -> &Arc<BeamGeometry> {
        self.projector.beams()
    }

    fn process(&mut self, frame: &LidarFrame) -> Result<&FrameOutput, Error> {
        let (result, features) = self.odometry.process_with_features(frame)?;
        self.frames += 1;
        if let Some(map) = self.map.as_mut() {
            map.add(frame, &result, Some(&features))?;
        }
        let keypoint_points = features
            .per_image
            .iter()
            .map(|c| keylo_core::keypoint_points(frame, c))
            .collect();
        let fitted_covariance = result
            .degeneracy
            .as_ref()
            .and_then(|d| d.covariance(1.0))
            .map(|h| {
                let last = self.last.as_ref().map(|l| l.result.pose);
                let c = frame_covariance(&self.noise, &matrix(&h), &result.pose, last.as_ref());
                array(&c)
            });
        Ok(self.last.insert(FrameOutput {
            result,
            features,
            keypoint_points,
            fitted_covariance,
        }))
    }

    /// Frames registered so far (since the last [`Frontend::reset`]).
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The output of the last frame registered.
    pub fn last(&self) -> Option<&FrameOutput> {
        self.last.as_ref()
    }

    /// The last frame's pose.
    pub fn pose(&self) -> Option<&Pose> {
        self.last.as_ref().map(FrameOutput::pose)
    }

    /// The cloud the last frame was registered with (after the downsampler, sensor frame).
    pub fn last_cloud(&self) -> Option<&keylo_core::PointCloud> {
        self.odometry.last_cloud()
    }

    /// The registrar's local map in the world frame (empty when it keeps none it can show).
    pub fn local_map(&self) -> Vec<Point3<f64>> {
        self.odometry.local_map()
    }

    /// SLAM hook: the motion from the last frame to the next (IMU, wheels) replaces the
    /// registrar's constant-velocity guess for the next frame ([`Odometry::set_motion_prior`]).
    pub fn set_motion_prior(&mut self, delta: &Pose) -> Result<(), Error> {
        Ok(self.odometry.set_motion_prior(delta)?)
    }

    /// SLAM hook: the last frame's pose becomes `pose` (a loop closure's correction); map
    /// and motion are kept ([`Odometry::set_pose`]).
    pub fn set_pose(&mut self, pose: &Pose) -> Result<(), Error> {
        Ok(self.odometry.set_pose(pose)?)
    }

    /// SLAM hook: starts over (map, motion, frame count and last output forgotten).
    pub fn reset(&mut self) -> Result<(), Error> {
        self.odometry.reset()?;
        self.frames = 0;
        self.last = None;
        Ok(())
    }

    /// Saves a global map of the frames registered from now on in `dir` (docs/maps.md):
    /// the world-frame cloud, voxelised, and keyframes with their clouds, keypoints and
    /// descriptors. [`Frontend::finish_map`] (or dropping the frontend) writes the cloud and
    /// `map.json`. A map already being saved is finished first.
    pub fn save_map(&mut self, dir: impl AsRef<Path>, settings: MapConfig) -> Result<(), Error> {
        self.finish_map()?;
        let source = format!(
            "frames fed to keylo's Frontend ({} before the map)",
            self.frames
        );
        self.map = Some(MapBuilder::create(dir.as_ref(), settings, &source)?);
        Ok(())
    }

    /// Finishes the map [`Frontend::save_map`] started: writes its cloud and `map.json` and
    /// returns what `map.json` says (`None` when no map was being saved).
    pub fn finish_map(&mut self) -> Result<Option<MapManifest>, Error> {
        match self.map.take() {
            Some(map) => Ok(Some(map.finish()?)),
            None => Ok(None),
        }
    }

    /// The stages, e.g. to reach a registrar's own methods.
    pub fn odometry(&self) -> &Odometry {
        &self.odometry
    }

    /// The stages, mutably.
    pub fn odometry_mut(&mut self) -> &mut Odometry {
        &mut self.odometry
    }
}

/// The per-frame stages of `raw` (its `[source]` ignored), plugins loaded when enabled and
/// `trust` allows the libraries the config names.
pub(crate) fn odometry_of(
    raw: &RawConfig,
    registry: Registry,
    trust: Trust,
) -> Result<Odometry, Error> {
    let mut raw = raw.clone();
    raw.table.remove("source");
    #[allow(unused_mut)] // mutated only with run-time plugins
    let mut registry = registry;
    #[cfg(feature = "plugins")]
    keylo_plugin::load_for_config(&mut registry, &raw, trust)?;
    #[cfg(not(feature = "plugins"))]
    keylo_core::config::check_trust(&raw, trust, &[])?;
    let mut config = registry.resolve(&raw)?;
    config.trust = trust;
    Ok(Odometry::build(&config, &registry)?)
}

/// The noise model fitted for `raw`'s registrar kind (KISS-ICP when it names none), else
/// plain `σ² H⁻¹` with σ = 0.03 m.
pub(crate) fn noise_of(raw: &RawConfig) -> NoiseModel {
    let kind = (raw.table.get("registrar"))
        .and_then(|r| r.get("kind"))
        .and_then(toml::Value::as_str)
        .unwrap_or("kiss-icp");
    NoiseModel::fitted(kind).unwrap_or_else(|| NoiseModel::plain(PLAIN_SIGMA_M))
}

/// `[source.projection]` of `raw`, or the default projection.
fn projection_of(raw: &RawConfig) -> Result<ProjectionConfig, Error> {
    let table = raw
        .table
        .get("source")
        .and_then(|s| s.get("projection"))
        .and_then(toml::Value::as_table);
    match table {
        None => Ok(ProjectionConfig::default()),
        Some(t) => parse_params::<ProjectionConfig>(t).map_err(|(path, message)| {
            Error::Config(keylo_core::ConfigError::Invalid {
                origin: raw.origin.clone(),
                path: format!("source.projection.{path}"),
                message,
            })
        }),
    }
}

impl Drop for Frontend {
    /// A map still being saved is finished, so the frames fed so far are kept.
    fn drop(&mut self) {
        if let Err(e) = self.finish_map() {
            tracing::warn!("the map being saved could not be finished: {e}");
        }
    }
}
