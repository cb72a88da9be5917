//! KITTI-style drift: relative errors over path segments of fixed lengths, per metre.
//!
//! What is computed (same as the KITTI odometry devkit's `calcSequenceErrors` and its
//! overall average, but in `f64`):
//!
//! 1. `dᵢ` = accumulated path length of the *reference* up to pose `i`.
//! 2. For every start `s = 0, step, 2·step, …` and every length `L`: the end `e` is the first
//!    pose with `dₑ > dₛ + L`; starts without such a pose are skipped for that `L`.
//! 3. Error pose `E = (Qₛ⁻¹ Qₑ)⁻¹ (Pₛ⁻¹ Pₑ)` (the devkit's inverse, same norm and angle).
//!    Segment errors are `‖t(E)‖ / L` and `angle(E) / L`.
//! 4. `translation_pct = 100 · mean(‖t(E)‖ / L)` over all segments of all lengths;
//!    `rotation_deg_per_100m = 100 · mean(angle_deg(E) / L)`.

use crate::associate::Associated;
use crate::pose_error::{relative_error, PoseRelation};
use crate::rpe::accumulated_distances;
use crate::EvalError;

/// The KITTI benchmark's segment lengths, metres.
pub const KITTI_LENGTHS: [f64; 8] = [100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0];

/// Options of [`kitti_drift`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DriftOptions {
    /// Segment lengths, metres (default [`KITTI_LENGTHS`]).
    pub lengths: Vec<f64>,
    /// Frames between segment starts (default 10, as the devkit).
    pub step: usize,
}

impl Default for DriftOptions {
    fn default() -> Self {
        Self {
            lengths: KITTI_LENGTHS.to_vec(),
            step: 10,
        }
    }
}

impl DriftOptions {
    /// KITTI lengths when the path is longer than 800 m, else 10 %, 20 %, …, 80 % of
    /// `path_length`, so that short (e.g. simulated) runs still get segments.
    pub fn for_path_length(path_length: f64) -> Self {
        let lengths = if path_length > KITTI_LENGTHS[7] {
            KITTI_LENGTHS.to_vec()
        } else {
            (1..=8).map(|k| path_length * k as f64 / 10.0).collect()
        };
        Self { lengths, step: 10 }
    }
}

/// Drift over path segments.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Drift {
    /// Mean translation error per distance travelled, percent (m per 100 m).
    pub translation_pct: f64,
    /// Mean rotation error per distance travelled, degrees per 100 m.
    pub rotation_deg_per_100m: f64,
    /// Number of segments averaged.
    pub segments: usize,
    /// The segment lengths used, metres.
    pub lengths: Vec<f64>,
}

/// KITTI-style drift of associated trajectories (see the module docs for the formula).
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// use keylo_eval::{associate::Associated, drift::{kitti_drift, DriftOptions}};
/// let mut gt = Trajectory::default();
/// let mut est = Trajectory::default();
/// for i in 0..300 {
///     gt.push(i as f64, Pose::translation(i as f64, 0.0, 0.0));
///     est.push(i as f64, Pose::translation(1.02 * i as f64, 0.0, 0.0)); // 2 % too long
/// }
/// let opts = DriftOptions { lengths: vec![100.0, 200.0], step: 10 };
/// let d = kitti_drift(&Associated::by_index(&gt, &est)?, &opts)?;
/// assert!(d.translation_pct > 2.0 && d.translation_pct < 2.05); // segments end just past L
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
pub fn kitti_drift(pairs: &Associated, opts: &DriftOptions) -> Result<Drift, EvalError> {
    pairs.ensure_paired()?;
    check_options(opts)?;
    let distances = accumulated_distances(&pairs.reference.poses);
    let (q, p) = (&pairs.reference.poses, &pairs.estimate.poses);
    let (mut t_sum, mut r_sum, mut segments) = (0.0, 0.0, 0);
    for start in (0..distances.len()).step_by(opts.step) {
        for &length in &opts.lengths {
            let Some(end) = segment_end(&distances, start, length) else {
                continue;
            };
            let e = relative_error(&q[start], &q[end], &p[start], &p[end]);
            t_sum += PoseRelation::Translation.of(&e) / length;
            r_sum += PoseRelation::AngleDeg.of(&e) / length;
            segments += 1;
        }
    }
    if segments == 0 {
        return Err(EvalError::NoSegments {
            path_length: distances.last().copied().unwrap_or(0.0),
            shortest: opts.lengths.iter().copied().fold(f64::INFINITY, f64::min),
        });
    }
    let n = segments as f64;
    Ok(Drift {
        translation_pct: 100.0 * t_sum / n,
        rotation_deg_per_100m: 100.0 * r_sum / n,
        segments,
        lengths: opts.lengths.clone(),
    })
}

/// First pose after `start` whose distance exceeds `distances[start] + length`.
fn segment_end(distances: &[f64], start: usize, length: f64) -> Option<usize> {
    let target = distances[start] + length;
    (start..distances.len()).find(|&i| distances[i] > target)
}

fn check_options(opts: &DriftOptions) -> Result<(), EvalError> {
    if opts.step == 0 {
        return Err(EvalError::InvalidOption {
            name: "drift step",
            reason: "must be at least 1 frame".to_string(),
        });
    }
    if opts.lengths.is_empty() || opts.lengths.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
        return Err(EvalError::InvalidOption {
            name: "drift lengths",
            reason: format!(
                "{:?} must be a non-empty list of positive distances",
                opts.lengths
            ),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::{Pose, Trajectory};
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    fn straight(n: usize, scale: f64) -> Trajectory {
        let mut t = Trajectory::default();
        for i in 0..n {
            t.push(i as f64, Pose::translation(scale * i as f64, 0.0, 0.0));
        }
        t
    }

    #[test]
    fn exact_segments_give_exact_percent() {
        // Steps of 0.5 m: a 50 m segment ends 50.5 m (101 poses) after its start, where the
        // estimate, 1 % too long, is off by 0.505 m; starts 0, 10, ..., 290 fit.
        let gt = straight(401, 0.5);
        let est = straight(401, 0.505);
        let opts = DriftOptions {
            lengths: vec![50.0],
            step: 10,
        };
        let d = kitti_drift(&Associated::by_index(&gt, &est).unwrap(), &opts).unwrap();
        assert_eq!(d.segments, 30);
        assert!((d.translation_pct - 1.01).abs() < 1e-9);
    }

    #[test]
    fn yaw_drift_shows_in_rotation() {
        let mut gt = Trajectory::default();
        let mut est = Trajectory::default();
        for i in 0..200 {
            gt.push(i as f64, Pose::translation(i as f64, 0.0, 0.0));
            let yaw =
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), (0.01 * i as f64).to_radians());
            est.push(
                i as f64,
                Pose::from_parts(Translation3::new(i as f64, 0.0, 0.0), yaw),
            );
        }
        let opts = DriftOptions {
            lengths: vec![100.0],
            step: 1,
        };
        let d = kitti_drift(&Associated::by_index(&gt, &est).unwrap(), &opts).unwrap();
        assert!(
            (d.rotation_deg_per_100m - 1.01).abs() < 1e-9,
            "{}",
            d.rotation_deg_per_100m
        );
    }

    #[test]
    fn too_short_and_bad_options() {
        let t = straight(10, 1.0);
        let pairs = Associated::by_index(&t, &t).unwrap();
        assert!(matches!(
            kitti_drift(&pairs, &DriftOptions::default()),
            Err(EvalError::NoSegments { .. })
        ));
        let bad = DriftOptions {
            lengths: vec![],
            step: 10,
        };
        assert!(matches!(
            kitti_drift(&pairs, &bad),
            Err(EvalError::InvalidOption { .. })
        ));
        assert_eq!(DriftOptions::for_path_length(9.0).lengths[0], 0.9);
    }
}
