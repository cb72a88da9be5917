//! Smooth, deterministic ground-truth motion along a closed planar curve.
//!
//! The sensor moves at constant speed along the curve (arc-length parameterised through a
//! dense table), heads along the tangent with a slow yaw sway, and carries small pitch/roll
//! oscillations and a small height bob. Positions and angles are continuous in time.

use std::f64::consts::{PI, TAU};

use keylo_core::Pose;
use nalgebra::{Translation3, UnitQuaternion, Vector2};

/// Samples of the arc-length table.
const TABLE_SAMPLES: usize = 20_000;

/// A closed planar curve, parameter `u ∈ [0, 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curve {
    /// An ellipse starting at `center + (a, 0)`, run counter-clockwise.
    Ellipse {
        /// Centre, metres.
        center: [f64; 2],
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
    },
    /// Two straights along x (`y = ±half_width`) from `x0` to `x1`, joined by half circles.
    Stadium {
        /// Start of the straights.
        x0: f64,
        /// End of the straights.
        x1: f64,
        /// Half the distance between the straights (the turn radius).
        half_width: f64,
    },
    /// An ellipse with a 2nd-harmonic bulge: `(a cos θ + w cos 2θ, b sin θ)`.
    Loop {
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
        /// Amplitude of the bulge.
        wobble: f64,
    },
}

impl Curve {
    /// Point at parameter `u` (periodic with period 1).
    pub fn point(&self, u: f64) -> Vector2<f64> {
        let u = u.rem_euclid(1.0);
        match *self {
            Curve::Ellipse { center, a, b } => {
                let th = TAU * u;
                Vector2::new(center[0] + a * th.cos(), center[1] + b * th.sin())
            }
            Curve::Stadium { x0, x1, half_width } => stadium(x0, x1, half_width, u),
            Curve::Loop { a, b, wobble } => {
                let th = TAU * u;
                Vector2::new(a * th.cos() + wobble * (2.0 * th).cos(), b * th.sin())
            }
        }
    }
}

/// Stadium with `u` proportional to arc length; starts at `(x0, -r)` heading +x.
fn stadium(x0: f64, x1: f64, r: f64, u: f64) -> Vector2<f64> {
    let straight = x1 - x0;
    let turn = PI * r;
    let s = u * 2.0 * (straight + turn);
    if s < straight {
        Vector2::new(x0 + s, -r)
    } else if s < straight + turn {
        let a = (s - straight) / r - PI / 2.0;
        Vector2::new(x1 + r * a.cos(), r * a.sin())
    } else if s < 2.0 * straight + turn {
        Vector2::new(x1 - (s - straight - turn), r)
    } else {
        let a = (s - 2.0 * straight - turn) / r + PI / 2.0;
        Vector2::new(x0 + r * a.cos(), r * a.sin())
    }
}

/// Small periodic attitude and height perturbations (radians, metres, hertz).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sway {
    /// Yaw amplitude about the heading.
    pub yaw_amp: f64,
    /// Pitch amplitude.
    pub pitch_amp: f64,
    /// Roll amplitude.
    pub roll_amp: f64,
    /// Height bob amplitude.
    pub bob_amp: f64,
    /// Base frequency; the four terms use fixed multiples of it.
    pub freq_hz: f64,
    /// Phase offset (from the seed).
    pub phase: f64,
}

/// Constant-speed motion along a [`Curve`].
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    curve: Curve,
    /// Cumulative arc length at `u = k / TABLE_SAMPLES`.
    lengths: Vec<f64>,
    speed: f64,
    height: f64,
    sway: Sway,
    /// Arc length at t = 0, metres.
    start: f64,
}

impl Motion {
    /// Motion along `curve` at `speed` m/s, `height` m above z = 0.
    pub fn new(curve: Curve, speed: f64, height: f64, sway: Sway) -> Self {
        let mut lengths = Vec::with_capacity(TABLE_SAMPLES + 1);
        let mut total = 0.0;
        let mut prev = curve.point(0.0);
        lengths.push(0.0);
        for k in 1..=TABLE_SAMPLES {
            let p = curve.point(k as f64 / TABLE_SAMPLES as f64);
            total += (p - prev).norm();
            lengths.push(total);
            prev = p;
        }
        Self {
            curve,
            lengths,
            speed,
            height,
            sway,
            start: 0.0,
        }
    }

    /// Starts the motion `share` of a lap (0 … 1) further along its curve.
    pub fn start_at(&mut self, share: f64) {
        self.start = share * self.lap_length();
    }

    /// The same motion with every sway amplitude times `k` (0: no sway).
    pub fn with_sway_scaled(mut self, k: f64) -> Self {
        let s = &mut self.sway;
        s.yaw_amp *= k;
        s.pitch_amp *= k;
        s.roll_amp *= k;
        s.bob_amp *= k;
        self
    }

    /// Length of one lap, metres.
    pub fn lap_length(&self) -> f64 {
        self.lengths.last().copied().unwrap_or(0.0)
    }

    /// Nominal sensor height above z = 0, metres.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Speed along the curve, m/s.
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Curve parameter at arc length `s` (wrapped to one lap).
    fn param_at(&self, s: f64) -> f64 {
        let total = self.lap_length();
        if total <= 0.0 {
            return 0.0;
        }
        let s = s.rem_euclid(total);
        let k = self
            .lengths
            .partition_point(|&l| l <= s)
            .clamp(1, TABLE_SAMPLES);
        let (l0, l1) = (self.lengths[k - 1], self.lengths[k]);
        let f = if l1 > l0 { (s - l0) / (l1 - l0) } else { 0.0 };
        (k as f64 - 1.0 + f) / TABLE_SAMPLES as f64
    }

    /// Planar position at arc length `s`.
    pub fn position_at_distance(&self, s: f64) -> Vector2<f64> {
        self.curve.point(self.param_at(s))
    }

    /// Heading (yaw of the tangent) at arc length `s`.
    fn heading_at_distance(&self, s: f64) -> f64 {
        let d = self.position_at_distance(s + 0.05) - self.position_at_distance(s - 0.05);
        d.y.atan2(d.x)
    }

    /// The sensor pose (sensor → world) at time `t`, seconds.
    pub fn pose_at(&self, t: f64) -> Pose {
        let s = self.start + self.speed * t;
        let p = self.position_at_distance(s);
        let w = TAU * self.sway.freq_hz * t + self.sway.phase;
        let yaw = self.heading_at_distance(s) + self.sway.yaw_amp * (0.37 * w).sin();
        let pitch = self.sway.pitch_amp * (1.3 * w + 0.5).sin();
        let roll = self.sway.roll_amp * (0.9 * w + 1.7).sin();
        let z = self.height + self.sway.bob_amp * (2.1 * w).sin();
        Pose::from_parts(
            Translation3::new(p.x, p.y, z),
            UnitQuaternion::from_euler_angles(roll, pitch, yaw),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sway() -> Sway {
        Sway {
            yaw_amp: 0.1,
            pitch_amp: 0.02,
            roll_amp: 0.02,
            bob_amp: 0.01,
            freq_hz: 0.5,
            phase: 0.3,
        }
    }

    #[test]
    fn constant_speed_along_curves() {
        let curves = [
            Curve::Ellipse {
                center: [0.0, 0.0],
                a: 4.0,
                b: 2.0,
            },
            Curve::Stadium {
                x0: 3.0,
                x1: 77.0,
                half_width: 0.6,
            },
            Curve::Loop {
                a: 150.0,
                b: 80.0,
                wobble: 12.0,
            },
        ];
        for c in curves {
            let m = Motion::new(c, 2.0, 1.5, sway());
            for k in 0..200 {
                let (s0, s1) = (k as f64 * 0.37, k as f64 * 0.37 + 0.2);
                let d = (m.position_at_distance(s1) - m.position_at_distance(s0)).norm();
                assert!((d - 0.2).abs() < 2e-3, "{c:?} at {s0}: {d}");
            }
        }
    }

    #[test]
    fn a_later_start_is_the_same_walk_further_along() {
        let c = Curve::Ellipse {
            center: [0.0, 0.0],
            a: 4.0,
            b: 2.0,
        };
        let usual = Motion::new(c, 2.0, 1.5, sway());
        let mut later = usual.clone();
        later.start_at(0.25);
        // A quarter lap of an ellipse from (a, 0) counter-clockwise ends at (0, b).
        let p = later.pose_at(0.0).translation.vector;
        assert!(p.x.abs() < 1e-3 && (p.y - 2.0).abs() < 1e-3, "{p}");
        let ahead = 0.25 * usual.lap_length() / 2.0;
        for t in [0.0, 0.7, 3.1] {
            let (a, b) = (later.pose_at(t), usual.pose_at(t + ahead));
            // The sway runs on time, not on the way walked: compare the planar positions.
            let d = (a.translation.vector.xy() - b.translation.vector.xy()).norm();
            assert!(d < 1e-9, "at {t}: {d}");
        }
        // A start of 0 is the usual walk.
        let mut same = usual.clone();
        same.start_at(0.0);
        assert_eq!(same.pose_at(1.3), usual.pose_at(1.3));
    }

    #[test]
    fn stadium_is_continuous_and_starts_heading_x() {
        let c = Curve::Stadium {
            x0: 3.0,
            x1: 77.0,
            half_width: 0.6,
        };
        for k in 0..10_000 {
            let u = k as f64 / 10_000.0;
            let d = (c.point(u + 1e-5) - c.point(u)).norm();
            assert!(d < 0.01, "{u}");
        }
        let m = Motion::new(c, 1.2, 1.5, sway());
        assert!(m.heading_at_distance(1.0).abs() < 1e-9);
        assert!((m.lap_length() - 2.0 * (74.0 + PI * 0.6)).abs() < 1e-3);
    }
}
