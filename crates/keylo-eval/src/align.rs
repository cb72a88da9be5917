//! Umeyama alignment (SE(3) or Sim(3)), as evo's `geometry.umeyama_alignment`.

use keylo_core::{Pose, Trajectory};
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};

use crate::EvalError;

/// A similarity `y ≈ scale · rotation · x + translation` (scale is 1 for SE(3)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Alignment {
    /// Rotation part.
    pub rotation: UnitQuaternion<f64>,
    /// Translation part.
    pub translation: Vector3<f64>,
    /// Scale factor (1 unless Sim(3) alignment was asked for).
    pub scale: f64,
    /// The rotation about the path's main axis was taken from the orientations, because the
    /// positions leave it undetermined (a nearly straight path; see [`crate::align_roll`]).
    /// Always `false` for a point-set alignment ([`umeyama`]).
    pub roll_from_orientations: bool,
}

impl Alignment {
    /// `scale · rotation · x + translation`, found from positions alone.
    pub fn new(rotation: UnitQuaternion<f64>, translation: Vector3<f64>, scale: f64) -> Self {
        Self {
            rotation,
            translation,
            scale,
            roll_from_orientations: false,
        }
    }

    /// The identity alignment.
    pub fn identity() -> Self {
        Self::new(UnitQuaternion::identity(), Vector3::zeros(), 1.0)
    }

    /// The rigid part `(rotation, translation)`, ignoring the scale.
    pub fn isometry(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.translation), self.rotation)
    }

    /// Maps a point: `scale · R · p + t`.
    pub fn transform_point(&self, p: &Point3<f64>) -> Point3<f64> {
        Point3::from(self.rotation * (p.coords * self.scale) + self.translation)
    }

    /// Maps a pose as evo does: its translation is scaled, then the rigid part is
    /// left-multiplied (`T · pose`).
    pub fn apply(&self, pose: &Pose) -> Pose {
        let scaled = Pose::from_parts(
            Translation3::from(pose.translation.vector * self.scale),
            pose.rotation,
        );
        self.isometry() * scaled
    }

    /// Maps every pose of a trajectory; stamps are kept.
    pub fn apply_trajectory(&self, traj: &Trajectory) -> Trajectory {
        Trajectory {
            stamps: traj.stamps.clone(),
            poses: traj.poses.iter().map(|p| self.apply(p)).collect(),
        }
    }
}

/// Least-squares similarity mapping points `x` onto points `y` (Umeyama 1991).
///
/// Same steps as evo: centre both sets, `Σ = (1/n) Σᵢ (yᵢ−μy)(xᵢ−μx)ᵀ`, `Σ = U D Vᵀ`,
/// `S = diag(1, 1, ±1)` (−1 when `det U · det V < 0`), `R = U S Vᵀ`,
/// `c = tr(D S) / σx²` (only `with_scale`, else 1), `t = μy − c R μx`.
/// Fails with fewer than 3 pairs or when fewer than 2 singular values exceed machine epsilon.
///
/// ```
/// use nalgebra::{Point3, UnitQuaternion, Vector3};
/// let x = [Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 2.0, 0.0), Point3::new(0.0, 0.0, 3.0)];
/// let q = UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3);
/// let y: Vec<_> = x.iter().map(|p| q * p + Vector3::new(1.0, 2.0, 3.0)).collect();
/// let a = keylo_eval::align::umeyama(&x, &y, false)?;
/// assert!(a.rotation.angle_to(&q) < 1e-12);
/// assert!((a.translation - Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-12);
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
pub fn umeyama(
    x: &[Point3<f64>],
    y: &[Point3<f64>],
    with_scale: bool,
) -> Result<Alignment, EvalError> {
    let fit = Fit::new(x, y, with_scale)?;
    if fit.rank < 2 {
        return Err(EvalError::Degenerate { rank: fit.rank });
    }
    Ok(fit.alignment(fit.rotation))
}

/// The pieces of an Umeyama fit that a later choice of rotation needs.
pub(crate) struct Fit {
    /// Number of point pairs.
    pub n: usize,
    /// Centroid of `x`.
    pub mean_x: Point3<f64>,
    /// Centroid of `y`.
    pub mean_y: Point3<f64>,
    /// Mean squared distance of `x` from its centroid.
    pub sigma_x: f64,
    /// Mean squared distance of `y` from its centroid.
    pub sigma_y: f64,
    /// The cross-covariance `(1/n) Σᵢ (yᵢ−μy)(xᵢ−μx)ᵀ`.
    pub cov: Matrix3<f64>,
    /// Its singular values, largest first.
    pub d: Vector3<f64>,
    /// Its left singular vectors (columns), in the order of `d`.
    pub u: Matrix3<f64>,
    /// `diag(s)` of the reflection guard.
    pub s: Vector3<f64>,
    /// Singular values above machine epsilon.
    pub rank: usize,
    /// Umeyama's rotation `U S Vᵀ`.
    pub rotation: Matrix3<f64>,
    /// Whether the scale is fitted (Sim(3)).
    pub with_scale: bool,
}

impl Fit {
    /// Centres, correlates and decomposes the pairs; fails only when no singular value is
    /// above machine epsilon (all points coincide).
    pub fn new(x: &[Point3<f64>], y: &[Point3<f64>], with_scale: bool) -> Result<Self, EvalError> {
        check_sizes(x, y)?;
        let (mean_x, mean_y) = (centroid(x), centroid(y));
        let n = x.len() as f64;
        let sigma_x = x.iter().map(|p| (p - mean_x).norm_squared()).sum::<f64>() / n;
        let sigma_y = y.iter().map(|p| (p - mean_y).norm_squared()).sum::<f64>() / n;
        let cov = covariance(x, y, &mean_x, &mean_y) / n;
        let svd = cov.svd(true, true);
        let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
            return Err(EvalError::Degenerate { rank: 0 });
        };
        let d = svd.singular_values;
        let rank = d.iter().filter(|&&s| s > f64::EPSILON).count();
        if rank == 0 {
            return Err(EvalError::Degenerate { rank });
        }
        let mut s = Vector3::new(1.0, 1.0, 1.0);
        if u.determinant() * v_t.determinant() < 0.0 {
            s.z = -1.0;
        }
        let rotation = u * Matrix3::from_diagonal(&s) * v_t;
        Ok(Self {
            n: x.len(),
            mean_x,
            mean_y,
            sigma_x,
            sigma_y,
            cov,
            d,
            u,
            s,
            rank,
            rotation,
            with_scale,
        })
    }

    /// The scale that is optimal for rotation `r`: `tr(Rᵀ Σ) / σx²` (1 without scale).
    pub fn scale_for(&self, r: &Matrix3<f64>) -> f64 {
        if self.with_scale {
            (r.transpose() * self.cov).trace() / self.sigma_x
        } else {
            1.0
        }
    }

    /// The alignment with rotation `r`, its optimal scale and translation.
    pub fn alignment(&self, r: Matrix3<f64>) -> Alignment {
        let scale = self.scale_for(&r);
        let translation = self.mean_y.coords - scale * (r * self.mean_x.coords);
        let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
        Alignment::new(rotation, translation, scale)
    }
}

fn check_sizes(x: &[Point3<f64>], y: &[Point3<f64>]) -> Result<(), EvalError> {
    if x.len() != y.len() {
        return Err(EvalError::LengthMismatch {
            reference: "target points".to_string(),
            reference_len: y.len(),
            estimate: "source points".to_string(),
            estimate_len: x.len(),
        });
    }
    if x.len() < 3 {
        return Err(EvalError::TooFewPoints { found: x.len() });
    }
    Ok(())
}

fn centroid(points: &[Point3<f64>]) -> Point3<f64> {
    let sum: Vector3<f64> = points.iter().map(|p| p.coords).sum();
    Point3::from(sum / points.len() as f64)
}

fn covariance(
    x: &[Point3<f64>],
    y: &[Point3<f64>],
    mx: &Point3<f64>,
    my: &Point3<f64>,
) -> Matrix3<f64> {
    x.iter()
        .zip(y)
        .map(|(px, py)| (py - my) * (px - mx).transpose())
        .sum()
}

/// Positions of a trajectory as points.
pub fn positions(traj: &Trajectory) -> Vec<Point3<f64>> {
    traj.poses
        .iter()
        .map(|p| Point3::from(p.translation.vector))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Vec<Point3<f64>> {
        (0..8)
            .map(|i| {
                Point3::new(
                    (i & 1) as f64,
                    ((i >> 1) & 1) as f64 * 2.0,
                    (i >> 2) as f64 * 3.0,
                )
            })
            .collect()
    }

    #[test]
    fn recovers_similarity() {
        let x = cube();
        let truth = Alignment::new(
            UnitQuaternion::from_euler_angles(-0.4, 0.9, 2.5),
            Vector3::new(-3.0, 4.0, 0.5),
            1.7,
        );
        let y: Vec<_> = x.iter().map(|p| truth.transform_point(p)).collect();
        let a = umeyama(&x, &y, true).unwrap();
        assert!(a.rotation.angle_to(&truth.rotation) < 1e-12);
        assert!((a.scale - 1.7).abs() < 1e-12);
        assert!((a.translation - truth.translation).norm() < 1e-12);
    }

    #[test]
    fn too_few_and_collinear_points_fail() {
        let two = [Point3::origin(), Point3::new(1.0, 0.0, 0.0)];
        assert!(matches!(
            umeyama(&two, &two, false),
            Err(EvalError::TooFewPoints { found: 2 })
        ));
        let line: Vec<_> = (0..5).map(|i| Point3::new(i as f64, 0.0, 0.0)).collect();
        assert!(matches!(
            umeyama(&line, &line, false),
            Err(EvalError::Degenerate { rank: 1 })
        ));
    }

    #[test]
    fn planar_points_are_fine() {
        let x: Vec<_> = (0..6)
            .map(|i| Point3::new(i as f64, (i * i) as f64, 0.0))
            .collect();
        let q = UnitQuaternion::from_euler_angles(0.0, 0.0, 1.0);
        let y: Vec<_> = x.iter().map(|p| q * p).collect();
        let a = umeyama(&x, &y, false).unwrap();
        assert!(a.rotation.angle_to(&q) < 1e-12);
    }

    #[test]
    fn apply_scales_translation_then_moves() {
        let a = Alignment::new(UnitQuaternion::identity(), Vector3::new(1.0, 0.0, 0.0), 2.0);
        let p = a.apply(&Pose::translation(1.0, 1.0, 1.0));
        assert_eq!(p.translation.vector, Vector3::new(3.0, 2.0, 2.0));
    }
}
