//! The NDT Newton loop with PCL's step and convergence rules (`computeTransformation`).

use nalgebra::{Isometry3, Matrix6, Point3, Vector6, SVD};

use super::euler::{params_of, pose_of};
use super::line_search::more_thuente;
use super::neighbours::NdtTarget;
use super::score::{derivatives, Derivatives, Gauss};
use crate::RegistrationError;

/// Solver parameters (PCL's names and defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlignSettings {
    /// Longest step of the line search along the normalised Newton direction (PCL 0.1).
    pub step_size: f64,
    /// Stop when a step's squared translation is at most this (PCL 0.1; ≤ 0: rotation rule
    /// only).
    pub transformation_epsilon: f64,
    /// Stop when a step's rotation has cos(angle) ≥ this (PCL 0 = unset).
    pub rotation_epsilon: f64,
    /// Newton iterations at most (PCL 35).
    pub max_iterations: usize,
    /// Outlier ratio of the Gaussian-plus-uniform score (PCL 0.55).
    pub outlier_ratio: f64,
}

impl Default for AlignSettings {
    fn default() -> Self {
        Self {
            step_size: 0.1,
            transformation_epsilon: 0.1,
            rotation_epsilon: 0.0,
            max_iterations: 35,
            outlier_ratio: 0.55,
        }
    }
}

/// The outcome of one alignment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NdtResult {
    /// The pose taking source points into the target frame.
    pub pose: Isometry3<f64>,
    /// Newton iterations run.
    pub iterations: usize,
    /// Whether PCL's convergence rule stopped the loop (false: the iteration cap did).
    pub converged: bool,
    /// Final score divided by the source size (PCL's transformation likelihood).
    pub likelihood: f64,
    /// The score's Hessian at the final pose, w.r.t. `[x y z roll pitch yaw]`.
    pub hessian: Matrix6<f64>,
}

/// Aligns `source` (sensor frame) to `target` from `guess`, as PCL's
/// `NormalDistributionsTransform::align` does.
pub fn align(
    target: &NdtTarget,
    source: &[Point3<f64>],
    guess: &Isometry3<f64>,
    settings: &AlignSettings,
) -> Result<NdtResult, RegistrationError> {
    if !keylo_core::rigid::is_finite(guess) {
        return Err(RegistrationError::BadGuess(format!(
            "NDT initial guess is not finite: {guess}"
        )));
    }
    if source.is_empty() {
        return Err(RegistrationError::BadCloud(
            "NDT source cloud is empty".into(),
        ));
    }
    let gauss = Gauss::new(settings.outlier_ratio, target.resolution());
    let eval = |p: &Vector6<f64>, h: bool| derivatives(target, source, p, gauss, h);
    let mut p = params_of(guess);
    let mut d = eval(&p, true);
    if d.score == 0.0 {
        // PCL reports this as converged at the guess (zero gradient); it is no alignment.
        return Err(RegistrationError::Diverged(format!(
            "NDT: from the initial guess no source point of {} falls near a target voxel",
            source.len()
        )));
    }
    let mut iterations = 0;
    let mut converged = false;
    let n = source.len() as f64;
    // PCL runs at least one iteration; the cap stops the loop without convergence.
    while iterations < settings.max_iterations.max(1) {
        let Some(delta) = newton_direction(&d) else {
            break;
        };
        let norm = delta.norm();
        if norm == 0.0 || norm.is_nan() {
            converged = norm == 0.0;
            break;
        }
        let step = line_step(&eval, &p, delta / norm, norm, settings, &mut d);
        p += step;
        iterations += 1;
        if small_step(&step, settings) {
            converged = true;
            break;
        }
    }
    let pose = pose_of(&p);
    if !pose.translation.vector.iter().all(|v| v.is_finite()) {
        return Err(RegistrationError::Diverged(
            "NDT produced a non-finite pose".into(),
        ));
    }
    Ok(NdtResult {
        pose,
        iterations,
        converged,
        likelihood: d.score / n,
        hessian: d.hessian,
    })
}

/// The Newton step −H⁻¹g (SVD solve, singular values below Eigen's JacobiSVD threshold
/// dropped); `None` when the derivatives are not finite or the SVD fails (the loop then
/// stops unconverged, as PCL's does when its SVD fails).
fn newton_direction(d: &Derivatives) -> Option<Vector6<f64>> {
    let finite = d
        .hessian
        .iter()
        .chain(d.gradient.iter())
        .all(|v| v.is_finite());
    if !finite {
        return None;
    }
    // Bounded SVD iterations: a pathological matrix ends the loop instead of spinning.
    let svd = SVD::try_new(d.hessian, true, true, f64::EPSILON, 10_000)?;
    let largest = svd.singular_values.max();
    let eps = largest * 6.0 * f64::EPSILON;
    svd.solve(&(-d.gradient), eps).ok()
}

/// One line search along `dir` (normalised) from `p`; updates `d` to the derivatives at the
/// new point and returns the step taken.
fn line_step(
    eval: &impl Fn(&Vector6<f64>, bool) -> Derivatives,
    p: &Vector6<f64>,
    mut dir: Vector6<f64>,
    norm: f64,
    settings: &AlignSettings,
    d: &mut Derivatives,
) -> Vector6<f64> {
    // φ(α) = −score(p + α·dir), minimised.
    let phi0 = -d.score;
    let mut dphi0 = -d.gradient.dot(&dir);
    if dphi0 >= 0.0 {
        if dphi0 == 0.0 {
            return Vector6::zeros();
        }
        dphi0 = -dphi0;
        dir = -dir;
    }
    let mut last_hessian = true;
    let step = more_thuente(
        phi0,
        dphi0,
        norm,
        settings.transformation_epsilon / 2.0,
        settings.step_size,
        |a, trial| {
            // The Hessian is only needed where the search stops; PCL computes it on the
            // first trial (usually accepted) and again at the end otherwise.
            last_hessian = trial == 0;
            *d = eval(&(p + dir * a), last_hessian);
            (-d.score, -d.gradient.dot(&dir))
        },
    );
    if !last_hessian {
        *d = eval(&(p + dir * step.length), true);
    }
    dir * step.length
}

/// PCL's rule on one step: squared translation ≤ ε (and/or cos(rotation) ≥ rotation ε).
fn small_step(step: &Vector6<f64>, s: &AlignSettings) -> bool {
    let t2 = step.fixed_rows::<3>(0).norm_squared();
    let rot = pose_of(&Vector6::new(0.0, 0.0, 0.0, step[3], step[4], step[5]));
    let cos_angle = rot.rotation.angle().cos();
    let eps_t = s.transformation_epsilon > 0.0;
    let eps_r = s.rotation_epsilon > 0.0;
    let t_ok = eps_t && t2 <= s.transformation_epsilon;
    let r_ok = eps_r && cos_angle >= s.rotation_epsilon;
    // PCL's three cases: both rules set and met, only the rotation rule, only translation.
    #[allow(clippy::nonminimal_bool)]
    let met = (t_ok && r_ok) || (!eps_t && r_ok) || (t_ok && !eps_r);
    met
}
