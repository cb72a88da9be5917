//! The simulator's parameters (`[source] kind = "sim"`).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::SimError;

/// Which synthetic world to fly the sensor through.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SceneKind {
    /// A 14 m × 9 m × 3 m room with furniture; the sensor walks a loop at ~1 m/s.
    #[default]
    Lab,
    /// An 80 m × 2.4 m × 3 m hall, geometrically degenerate along its axis, with posters;
    /// the sensor walks along it at ~1.2 m/s.
    Corridor,
    /// A closed loop road of ~750 m with buildings, gaps, poles, trees and parked cars;
    /// the sensor drives at ~8 m/s.
    Road,
    /// An unstructured outdoor scene: a ~270 m gravel path through a wooded park over
    /// rolling grass (trees, bushes, rocks, mounds, a few benches and lamp posts); the sensor
    /// is carried at ~1.4 m/s.
    Park,
}

impl SceneKind {
    /// The config name of the scene.
    pub fn name(self) -> &'static str {
        match self {
            Self::Lab => "lab",
            Self::Corridor => "corridor",
            Self::Road => "road",
            Self::Park => "park",
        }
    }
}

/// Which Ouster-like sensor to simulate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SensorKind {
    /// 128 beams over +45°..−45° elevation, 75 m max range.
    #[default]
    #[serde(rename = "os0-128")]
    Os0_128,
    /// 64 beams over +22.5°..−22.5° elevation, 120 m max range.
    #[serde(rename = "os1-64")]
    Os1_64,
}

/// Column counts per revolution the simulator accepts.
pub const ALLOWED_COLUMNS: [usize; 3] = [512, 1024, 2048];

/// Parameters of the simulated source.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    /// Synthetic world: `lab`, `corridor`, `road` or `park`.
    pub scene: SceneKind,
    /// Number of frames (sensor revolutions) to produce, at least 1.
    pub frames: usize,
    /// Sensor model: `os0-128` or `os1-64`.
    pub sensor: SensorKind,
    /// Columns per revolution: 512, 1024 or 2048.
    pub columns: usize,
    /// Seed of the scene layout, the surface textures and the measurement noise.
    pub seed: u64,
    /// Standard deviation of the Gaussian range noise, metres (0 = noise-free ranges).
    pub range_noise_m: f64,
    /// Cast each column from the sensor pose at its own firing time (true), or every column
    /// from the pose at the frame start (false, all column times equal the frame timestamp).
    pub motion_distortion: bool,
    /// Maximum range in metres; 0 = the sensor's default (75 m OS0, 120 m OS1).
    pub max_range_m: f64,
    /// Multiplier of the scene's nominal trajectory speed (0 = a static sensor).
    pub speed_scale: f64,
    /// Seconds over which the sensor accelerates smoothly from rest to full speed (as a
    /// recording that starts with the robot standing); 0 = full speed from the first frame.
    pub start_ramp_s: f64,
    /// Where on its loop the sensor starts, as a share of the lap from the scene's usual start
    /// (0 ≤ `start_lap` < 1; in the lab 0.25 starts on the straightest stretch of its ellipse,
    /// 7 m of turn radius against 1.1 m at 0).
    pub start_lap: f64,
    /// Multiplier of the scene's sway (the small yaw, pitch, roll and height oscillation of a
    /// carried sensor); 0 with `speed_scale = 0` holds the sensor still.
    pub sway_scale: f64,
    /// `ouster` (the default; every simulated sensor is an Ouster), or `ideal` (the shading
    /// model alone, the default until 2026-12-05): `ouster` is what real OS0-128 signal images show
    /// — their signal level in counts, per-beam gains that wander with range, shot noise,
    /// near-field and grazing fall-off, weak returns that break up, pixels that read a
    /// fraction of their signal now and then or beside a range jump, and (OS0-128) a real
    /// sensor's staggered beams, whose offsets and beam origins leave near vertical edges
    /// ragged — and, in the lab, a 16.5 m × 11 m hall, 4.5 m high, with painted walls, a
    /// dark floor with marks on it, clutter along the walls and people, stands and racks near
    /// the path. Its signal images look like the real ones made as Ouster's ROS driver makes
    /// them (`[image.normalise] method = "ouster-ros"`; docs/results/sim-realism.md).
    pub appearance: crate::Appearance,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            scene: SceneKind::Lab,
            frames: 100,
            sensor: SensorKind::Os0_128,
            columns: 1024,
            seed: 0,
            range_noise_m: 0.01,
            motion_distortion: true,
            max_range_m: 0.0,
            speed_scale: 1.0,
            start_ramp_s: 2.0,
            start_lap: 0.0,
            sway_scale: 1.0,
            appearance: crate::Appearance::Ouster,
        }
    }
}

impl SimConfig {
    /// `max_range_m` when set (non-zero).
    pub fn max_range_override(&self) -> Option<f64> {
        (self.max_range_m != 0.0).then_some(self.max_range_m)
    }

    /// Checks every field; the error names the first offending one.
    pub fn validate(&self) -> Result<(), SimError> {
        if self.frames == 0 {
            return Err(SimError::config("frames", "must be at least 1"));
        }
        if !ALLOWED_COLUMNS.contains(&self.columns) {
            return Err(SimError::config(
                "columns",
                format!("{} is not allowed; allowed: 512, 1024, 2048", self.columns),
            ));
        }
        if !self.range_noise_m.is_finite() || self.range_noise_m < 0.0 {
            return Err(SimError::config(
                "range_noise_m",
                format!("{} must be finite and ≥ 0", self.range_noise_m),
            ));
        }
        if !self.speed_scale.is_finite() || self.speed_scale < 0.0 {
            return Err(SimError::config(
                "speed_scale",
                format!("{} must be finite and ≥ 0", self.speed_scale),
            ));
        }
        if !self.sway_scale.is_finite() || self.sway_scale < 0.0 {
            return Err(SimError::config(
                "sway_scale",
                format!("{} must be finite and ≥ 0", self.sway_scale),
            ));
        }
        if !self.start_ramp_s.is_finite() || self.start_ramp_s < 0.0 {
            return Err(SimError::config(
                "start_ramp_s",
                format!("{} must be finite and ≥ 0", self.start_ramp_s),
            ));
        }
        if !(0.0..1.0).contains(&self.start_lap) {
            return Err(SimError::config(
                "start_lap",
                format!("{} must be ≥ 0 and < 1", self.start_lap),
            ));
        }
        if let Some(r) = self.max_range_override() {
            let min = crate::sensor::MIN_RANGE_M;
            if !r.is_finite() || r <= min || r > 1000.0 {
                return Err(SimError::config(
                    "max_range_m",
                    format!("{r} must be finite, > {min} (the minimum range) and ≤ 1000"),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field_of(c: SimConfig) -> Option<&'static str> {
        c.validate().err().and_then(|e| e.field())
    }

    #[test]
    fn default_is_valid() {
        assert!(SimConfig::default().validate().is_ok());
    }

    #[test]
    fn errors_name_the_field() {
        let d = SimConfig::default;
        assert_eq!(field_of(SimConfig { frames: 0, ..d() }), Some("frames"));
        assert_eq!(
            field_of(SimConfig {
                columns: 1000,
                ..d()
            }),
            Some("columns")
        );
        let c = SimConfig {
            range_noise_m: f64::NAN,
            ..d()
        };
        assert_eq!(field_of(c), Some("range_noise_m"));
        let c = SimConfig {
            range_noise_m: -0.1,
            ..d()
        };
        assert_eq!(field_of(c), Some("range_noise_m"));
        let c = SimConfig {
            speed_scale: f64::INFINITY,
            ..d()
        };
        assert_eq!(field_of(c), Some("speed_scale"));
        for start_lap in [1.0, -0.1, f64::NAN] {
            let c = SimConfig { start_lap, ..d() };
            assert_eq!(field_of(c), Some("start_lap"), "{start_lap}");
        }
        let c = SimConfig {
            max_range_m: 0.1,
            ..d()
        };
        assert_eq!(field_of(c), Some("max_range_m"));
        let msg = SimConfig { columns: 7, ..d() }
            .validate()
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("columns") && msg.contains("512, 1024, 2048"),
            "{msg}"
        );
    }

    #[test]
    fn serde_names_are_kebab_case() {
        let text = "scene = \"corridor\"\nsensor = \"os1-64\"\ncolumns = 2048\n";
        let c: SimConfig = toml::from_str(text).unwrap();
        assert_eq!(c.scene, SceneKind::Corridor);
        assert_eq!(c.sensor, SensorKind::Os1_64);
        assert_eq!(c.columns, 2048);
        assert_eq!(c.frames, 100);
        let back = toml::to_string(&c).unwrap();
        assert!(
            back.contains("\"os1-64\"") && back.contains("max_range_m = 0.0"),
            "{back}"
        );
        assert!(toml::from_str::<SimConfig>("colums = 1").is_err());
    }
}
