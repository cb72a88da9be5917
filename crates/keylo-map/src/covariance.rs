//! Pose covariances between frames and keyframes, from keylo's per-frame estimate.
//!
//! A registrar's covariance (`Degeneracy::covariance`) is that of a world-frame
//! perturbation `δ` of the frame's pose: `T_true = exp(δ) · T`. The relative motion
//! `Δ = T_a⁻¹ · T_b` is then perturbed on the right, `Δ_true = Δ · exp(ε)` with
//! `ε = Ad(T_b⁻¹) · δ`. Over several frames whose registration errors are independent,
//! `Σ_ab = Ad(T_b⁻¹) · (Σ_{k=a+1..b} Σ_δk) · Ad(T_b⁻¹)ᵀ` to first order: the world-frame
//! covariances add, then turn into the last frame's body frame. Twists are `[ρ, φ]`.

use keylo_core::Pose;
use nalgebra::{Matrix3, Matrix6};

/// The residual σ (m) of plain `σ² H⁻¹` for a registrar without a fitted model.
pub const PLAIN_SIGMA_M: f64 = 0.03;

/// A frame's motion covariance: the registrar's `H⁻¹` scaled, plus noise that grows with the
/// distance `d` the frame moved and the angle `a` it turned,
/// `diag((κ_t·d)² I₃, ((κ_r·d)² + (κ_a·a)²) I₃)` (m², rad²): odometry drift proportional to
/// the motion, which `H⁻¹` (the geometry's constraint on one alignment) does not see. Fitted
/// per registrar against simulated ground truth ([`NoiseModel::fitted`],
/// `examples/covariance_nees.rs`, docs/results/maps.md).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NoiseModel {
    /// Multiplies `H⁻¹` (m²: `σ²` of the residuals).
    pub scale: f64,
    /// Translation noise per metre moved (m/m).
    pub kappa_t: f64,
    /// Rotation noise per metre moved (rad/m).
    pub kappa_r: f64,
    /// Rotation noise per radian turned (rad/rad).
    pub kappa_a: f64,
}

impl NoiseModel {
    /// Just `σ² H⁻¹`.
    pub fn plain(sigma: f64) -> Self {
        Self {
            scale: sigma * sigma,
            kappa_t: 0.0,
            kappa_r: 0.0,
            kappa_a: 0.0,
        }
    }

    /// The model a run uses: plain `σ² H⁻¹` for a configured `sigma > 0`, else the model
    /// fitted for `registrar`, else (a registrar without one, with a warning naming `key`, the
    /// setting that chooses σ) plain `σ² H⁻¹` with [`PLAIN_SIGMA_M`].
    pub fn for_registrar(registrar: &str, sigma: f64, key: &str) -> Self {
        if sigma > 0.0 {
            return Self::plain(sigma);
        }
        Self::fitted(registrar).unwrap_or_else(|| {
            tracing::warn!(
                "no fitted covariance model for registrar `{registrar}`; σ²H⁻¹ with σ = \
                 {PLAIN_SIGMA_M} m (set {key})"
            );
            Self::plain(PLAIN_SIGMA_M)
        })
    }

    /// The model fitted for a built-in registrar kind; `None` for others (plugins).
    pub fn fitted(registrar: &str) -> Option<Self> {
        FITTED
            .iter()
            .find(|(k, _)| *k == registrar)
            .map(|(_, m)| *m)
    }

    /// The covariance of a motion whose `H⁻¹` (σ = 1) is `h_inv`, in any frame the motion
    /// noise is isotropic in (the motion's own), after moving `distance` m and turning
    /// `angle` rad.
    pub fn covariance(&self, h_inv: &Matrix6<f64>, distance: f64, angle: f64) -> Matrix6<f64> {
        let mut c = h_inv * self.scale;
        let t = (self.kappa_t * distance).powi(2);
        let r = (self.kappa_r * distance).powi(2) + (self.kappa_a * angle).powi(2);
        for k in 0..3 {
            c[(k, k)] += t;
            c[(k + 3, k + 3)] += r;
        }
        c
    }
}

/// The world-frame covariance (a perturbation `T_true = exp(δ)·T`, as the registrars'
/// `H⁻¹`) of the frame at `pose` under `noise`, given its `H⁻¹` (σ = 1, world frame) and the
/// previous frame's pose (`None`: no motion terms).
pub fn frame_covariance(
    noise: &NoiseModel,
    h_inv_world: &Matrix6<f64>,
    pose: &Pose,
    last: Option<&Pose>,
) -> Matrix6<f64> {
    let (distance, angle) = last.map_or((0.0, 0.0), |l| {
        let m = l.inverse() * pose;
        (m.translation.vector.norm(), m.rotation.angle())
    });
    let body = noise.covariance(&relative(pose, h_inv_world), distance, angle);
    let a = adjoint(pose);
    let c = a * body * a.transpose();
    (c + c.transpose()) * 0.5
}

/// The fitted models (`examples/covariance_nees.rs 10 80`: keyframe edges of the simulated
/// lab and road, seeds 0–4; checked on seeds 5–9, docs/results/maps.md).
const FITTED: [(&str, NoiseModel); 3] = [
    (
        "kiss-icp",
        NoiseModel {
            scale: 1.7782794100389228e-3,
            kappa_t: 5.623413251903491e-2,
            kappa_r: 3.1622776601683794e-3,
            kappa_a: 1.778279410038923e-1,
        },
    ),
    (
        "ndt",
        NoiseModel {
            scale: 3.1622776601683794e-3,
            kappa_t: 1.778279410038923e-2,
            kappa_r: 5.623413251903491e-3,
            kappa_a: 5.623413251903491e-2,
        },
    ),
    (
        "hybrid",
        NoiseModel {
            scale: 5.623413251903491e-4,
            kappa_t: 1.778279410038923e-2,
            kappa_r: 3.1622776601683794e-3,
            kappa_a: 1e-1,
        },
    ),
];

/// `[[f64; 6]; 6]` (as `Degeneracy::covariance` gives it) as a matrix.
pub fn matrix(c: &[[f64; 6]; 6]) -> Matrix6<f64> {
    Matrix6::from_fn(|i, j| c[i][j])
}

/// A matrix as `[[f64; 6]; 6]` (the inverse of [`matrix`]).
pub fn array(c: &Matrix6<f64>) -> [[f64; 6]; 6] {
    std::array::from_fn(|i| std::array::from_fn(|j| c[(i, j)]))
}

/// The adjoint of `T` on twists `[ρ, φ]`: `exp(Ad(T)·ξ) = T·exp(ξ)·T⁻¹`.
pub fn adjoint(t: &Pose) -> Matrix6<f64> {
    let r: Matrix3<f64> = t.rotation.to_rotation_matrix().into_inner();
    let p = t.translation.vector;
    let hat = Matrix3::new(0.0, -p.z, p.y, p.z, 0.0, -p.x, -p.y, p.x, 0.0);
    let mut a = Matrix6::zeros();
    a.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
    a.fixed_view_mut::<3, 3>(0, 3).copy_from(&(hat * r));
    a.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
    a
}

/// The covariance of the right perturbation `ε` of a relative motion ending at `t_b`, from
/// the sum of the world-frame covariances of the frames it spans.
pub fn relative(t_b: &Pose, world_sum: &Matrix6<f64>) -> Matrix6<f64> {
    let a = adjoint(&t_b.inverse());
    let c = a * world_sum * a.transpose();
    (c + c.transpose()) * 0.5
}

/// The information matrix an `EDGE_SE3:QUAT` line carries for a right-perturbation
/// covariance `c`, in the order `[Δt, Δθ]` with `Δθ` the rotation vector: how GTSAM's
/// `readG2o` and Ceres' `pose_graph_3d` read it (checked against GTSAM in the tests). g2o's
/// own `EdgeSE3` measures rotation by the quaternion's vector part, half the angle, so in g2o
/// the rotation block weighs 4× less (docs/maps.md). `None` when `c` is singular.
pub fn g2o_information(c: &Matrix6<f64>) -> Option<Matrix6<f64>> {
    let info = c.try_inverse()?;
    let info = (info + info.transpose()) * 0.5;
    info.iter().all(|v| v.is_finite()).then_some(info)
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_registration::se3;
    use nalgebra::{Vector3, Vector6};

    fn pose(t: [f64; 3], r: [f64; 3]) -> Pose {
        Pose::new(Vector3::from(t), Vector3::from(r))
    }

    #[test]
    fn the_adjoint_moves_a_twist_through_a_pose() {
        let t = pose([1.0, -2.0, 0.5], [0.3, -0.2, 1.1]);
        let xi = Vector6::new(0.01, -0.02, 0.03, 0.002, -0.001, 0.004);
        let lhs = se3::exp(&(adjoint(&t) * xi));
        let rhs = t * se3::exp(&xi) * t.inverse();
        assert!(se3::log(&(lhs.inverse() * rhs)).norm() < 1e-12);
    }

    #[test]
    fn a_frames_covariance_adds_the_motion_terms_in_its_own_frame() {
        let last = pose([1.0, 0.0, 0.0], [0.0, 0.0, 0.2]);
        let now = pose([1.8, 0.6, 0.0], [0.0, 0.0, 0.5]);
        let h = Matrix6::from_diagonal(&Vector6::new(1.0, 2.0, 3.0, 0.1, 0.2, 0.3));
        let noise = NoiseModel {
            scale: 0.01,
            kappa_t: 0.05,
            kappa_r: 0.003,
            kappa_a: 0.2,
        };
        // Without motion terms: s·H⁻¹, in the world frame, as given.
        let plain = frame_covariance(
            &NoiseModel {
                kappa_t: 0.0,
                kappa_r: 0.0,
                kappa_a: 0.0,
                ..noise
            },
            &h,
            &now,
            Some(&last),
        );
        assert!((plain - h * 0.01).norm() < 1e-15);
        // With them: in the frame's own frame, the diagonal grows by (κ_t d)² and (κ_r d)² + (κ_a a)².
        let c = frame_covariance(&noise, &h, &now, Some(&last));
        let body = relative(&now, &(c - plain));
        let (d, a): (f64, f64) = (1.0, 0.3);
        let want = Vector6::new(0.05f64.powi(2), 0.0025, 0.0025, 0.0, 0.0, 0.0) * d * d
            + Vector6::new(0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
                * ((0.003 * d).powi(2) + (0.2 * a).powi(2));
        assert!(
            (body - Matrix6::from_diagonal(&want)).norm() < 1e-12,
            "{body}"
        );
        // The first frame has no motion.
        assert!((frame_covariance(&noise, &h, &now, None) - h * 0.01).norm() < 1e-15);
    }

    /// The first-order relative covariance against perturbations drawn and pushed through
    /// the poses: `ε = log(Δ⁻¹ · Δ_true)` for `T_true = exp(δ) · T`.
    #[test]
    fn relative_covariance_matches_perturbed_poses() {
        let ta = pose([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]);
        let tb = pose([3.0, 1.0, -0.5], [0.1, -0.3, 0.8]);
        // A world-frame δ along each axis in turn: ε must be Ad(T_b⁻¹) δ.
        for k in 0..6 {
            let mut delta = Vector6::zeros();
            delta[k] = 1e-6;
            let truth_b = se3::exp(&delta) * tb;
            let eps = se3::log(&((ta.inverse() * tb).inverse() * (ta.inverse() * truth_b)));
            let want = adjoint(&tb.inverse()) * delta;
            assert!((eps - want).norm() < 1e-12, "axis {k}: {eps} vs {want}");
        }
        let world = Matrix6::from_diagonal(&Vector6::new(1e-4, 2e-4, 3e-4, 1e-6, 2e-6, 3e-6));
        let c = relative(&tb, &world);
        let a = adjoint(&tb.inverse());
        assert!((c - a * world * a.transpose()).norm() < 1e-18);
        let info = g2o_information(&c).unwrap();
        assert!((info * c - Matrix6::identity()).norm() < 1e-9);
    }
}
