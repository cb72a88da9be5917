//! The simulator: a validated config, its scene, and frames / ground truth on demand.

use keylo_core::{LidarFrame, Pose, Trajectory};

use crate::render::Renderer;
use crate::scenes::Scene;
use crate::sensor::SensorModel;
use crate::shading::{signal_gain, Shading};
use crate::{SensorKind, SimConfig, SimError};

/// Generates the frames and the ground truth of one [`SimConfig`].
///
/// Frame `i` starts at `t0 = i · period` (0.1 s); its columns fire at
/// `t0 + c/cols · period` (or all at `t0` without motion distortion). Frames are pure
/// functions of the config and the index: bit-identical across runs and thread counts.
#[derive(Debug)]
pub struct Simulator {
    config: SimConfig,
    scene: Scene,
    renderer: Renderer,
    /// Inverse of the world pose at frame 0's ground-truth stamp.
    reference: Pose,
}

impl Simulator {
    /// Validates `config` and builds its scene.
    pub fn new(config: &SimConfig) -> Result<Self, SimError> {
        config.validate()?;
        let sensor = SensorModel::new(config.sensor, config.columns, config.max_range_override());
        let sensor = if config.appearance.staggered_beams() {
            sensor.staggered()
        } else {
            sensor
        };
        let mut scene = Scene::build(
            config.scene,
            config.seed,
            config.speed_scale,
            config.sway_scale,
            config.appearance,
        )?;
        scene.motion.start_at(config.start_lap);
        let rated = match config.sensor {
            SensorKind::Os0_128 => 35.0,
            SensorKind::Os1_64 => 45.0,
        };
        let shading = Shading {
            range_noise_m: config.range_noise_m,
            min_range_m: sensor.min_range_m,
            max_range_m: sensor.max_range_m,
            signal_gain: signal_gain(rated),
            ambient: scene.ambient,
            near_field_m: config.appearance.near_field_m(),
            noise_factor: config.appearance.noise_factor(),
            dropout_counts: config.appearance.dropout_counts(),
            min_return_counts: config.appearance.min_return_counts(),
            grazing_power: config.appearance.grazing_power(),
            partial_drops: config.appearance.partial_drops(),
            mixed_pixels: config.appearance.mixed_pixels(),
        };
        let mut sim = Self {
            config: config.clone(),
            scene,
            renderer: Renderer::new(sensor, shading, config.seed, config.appearance),
            reference: Pose::identity(),
        };
        sim.reference = sim.pose_at(sim.gt_stamp(0)).inverse();
        Ok(sim)
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// Number of frames (`config.frames`).
    pub fn len(&self) -> usize {
        self.config.frames
    }

    /// Always false: a valid config has at least one frame.
    pub fn is_empty(&self) -> bool {
        self.config.frames == 0
    }

    /// The sensor intrinsics.
    pub fn sensor(&self) -> &SensorModel {
        &self.renderer.sensor
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Start time of frame `index`, seconds.
    pub fn frame_start(&self, index: usize) -> f64 {
        index as f64 * self.sensor().period()
    }

    /// Firing times of the columns of frame `index`.
    pub fn column_times(&self, index: usize) -> Vec<f64> {
        let t0 = self.frame_start(index);
        let s = self.sensor();
        (0..s.cols)
            .map(|c| {
                if self.config.motion_distortion {
                    t0 + s.column_offset(c)
                } else {
                    t0
                }
            })
            .collect()
    }

    /// Ground-truth stamp of frame `index`: its last column's time (`t0` without distortion).
    pub fn gt_stamp(&self, index: usize) -> f64 {
        let s = self.sensor();
        let t0 = self.frame_start(index);
        if self.config.motion_distortion {
            t0 + s.column_offset(s.cols - 1)
        } else {
            t0
        }
    }

    /// The sensor pose in the scene's world frame (sensor → world) at time `t`.
    /// The trajectory runs on warped time (see [`start_ramp`]) so that it starts from rest.
    pub fn pose_at(&self, t: f64) -> Pose {
        self.scene
            .motion
            .pose_at(start_ramp(t, self.config.start_ramp_s))
    }

    /// The sensor pose at `t` relative to the ground-truth pose of frame 0.
    pub fn relative_pose_at(&self, t: f64) -> Pose {
        self.reference * self.pose_at(t)
    }

    /// Renders frame `index` (any index; the trajectory is defined for all times).
    pub fn frame(&self, index: usize) -> LidarFrame {
        let times = self.column_times(index);
        let poses: Vec<Pose> = times.iter().map(|&t| self.pose_at(t)).collect();
        let t0 = self.frame_start(index);
        self.renderer
            .frame(&self.scene, index as u64, t0, times, &poses)
    }

    /// One pose per frame, stamped at [`Self::gt_stamp`], relative to frame 0 (first pose is
    /// the identity).
    pub fn ground_truth(&self) -> Trajectory {
        let mut t = Trajectory::default();
        for i in 0..self.len() {
            let stamp = self.gt_stamp(i);
            let pose = if i == 0 {
                Pose::identity()
            } else {
                self.relative_pose_at(stamp)
            };
            t.push(stamp, pose);
        }
        t
    }
}

/// Time warp for a smooth start from rest: the motion's clock runs at rate
/// `(1 − cos(π t / T)) / 2` during the first `T` seconds (0 → 1, continuous acceleration) and
/// at rate 1 afterwards; before t = 0 the sensor stands still.
pub fn start_ramp(t: f64, ramp: f64) -> f64 {
    if ramp <= 0.0 {
        return t;
    }
    if t <= 0.0 {
        0.0
    } else if t < ramp {
        t / 2.0 - ramp / (2.0 * std::f64::consts::PI) * (std::f64::consts::PI * t / ramp).sin()
    } else {
        t - ramp / 2.0
    }
}

#[cfg(test)]
mod ramp_tests {
    use super::start_ramp;

    #[test]
    fn ramp_is_continuous_and_starts_at_rest() {
        let (t, r) = (2.0, 2.0);
        assert!((start_ramp(t - 1e-9, r) - start_ramp(t + 1e-9, r)).abs() < 1e-8);
        // Rate: ~0 at the start, ~1 after the ramp.
        let rate = |x: f64| (start_ramp(x + 1e-6, r) - start_ramp(x, r)) / 1e-6;
        assert!(rate(1e-4) < 1e-3);
        assert!((rate(1.0) - 0.5).abs() < 1e-4);
        assert!((rate(3.0) - 1.0).abs() < 1e-6);
        assert_eq!(start_ramp(5.0, 0.0), 5.0);
        assert_eq!(start_ramp(-1.0, 2.0), 0.0);
    }
}
