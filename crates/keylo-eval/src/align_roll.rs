//! The rotation about a nearly straight path's axis, which its positions cannot fix.
//!
//! Umeyama's rotation `R₀ = U S Vᵀ` maximises `tr(Rᵀ Σ)`. Turning it by `θ` about the
//! reference's main axis `a = U e₁` leaves the fit of the positions along that axis alone and
//! changes `tr(Rᵀ Σ)` from `tr(D S)` to `d₀ + cos θ (d₁ + s₂ d₂)`: the mean squared position
//! residual `r²` grows by `2c (1 − cos θ)(d₁ + s₂ d₂)`. On a straight path `d₁ + s₂ d₂` is
//! (nearly) zero, so the positions' noise picks `θ`, and evo reports rotation errors of tens
//! or hundreds of degrees for an estimate whose orientations are right (160° on KITTI 00's
//! first ten scans).
//!
//! How well the positions fix that roll: under white position noise, the least-squares roll
//! has the standard error `σ_θ = √(r² / (3 n c (d₁ + s₂ d₂)))` (the residual spread over
//! three axes, against the curvature `n c (d₁ + s₂ d₂)` of the cost in `θ`). When `σ_θ`
//! exceeds [`MAX_ROLL_STD_ERROR_DEG`], keylo takes the roll that best aligns the orientations
//! instead: the `θ` maximising `Σᵢ tr(Q_iᵀ Rot(a, θ) R₀ P_i)` (estimate rotations `P_i`,
//! reference rotations `Q_i`), in closed form `θ = atan2(tr([a]× M), tr M − aᵀ M a)` with
//! `M = Σᵢ R₀ P_i Q_iᵀ`. Measured `σ_θ`: 0.17–0.83° on evo's test trajectories (noisy, but
//! curved), 9.5° on KITTI 00's first ten scans and 15.7° on 200 frames of the simulated
//! corridor (straight).

use keylo_core::Trajectory;
use nalgebra::{Matrix3, Unit, UnitQuaternion, Vector3};

use crate::align::{positions, Alignment, Fit};
use crate::EvalError;

/// Above this standard error of the roll left by the positions (degrees), the roll comes
/// from the orientations: between the curved paths' ≤ 0.83° and the straight ones' ≥ 9.5°
/// (module docs), and above the few degrees of rotation error odometry itself makes.
pub const MAX_ROLL_STD_ERROR_DEG: f64 = 3.0;

/// Umeyama's alignment, with the roll about the main axis taken from the orientations when
/// the positions leave it open (see the module docs).
pub(crate) fn resolve(
    fit: &Fit,
    estimate: &Trajectory,
    reference: &Trajectory,
) -> Result<Alignment, EvalError> {
    if roll_std_error_deg(fit) <= MAX_ROLL_STD_ERROR_DEG {
        return Ok(fit.alignment(fit.rotation));
    }
    let axis = Unit::new_normalize(fit.u.column(0).into_owned());
    let theta = orientation_roll(&fit.rotation, &axis, estimate, reference);
    let turn = UnitQuaternion::from_axis_angle(&axis, theta).to_rotation_matrix();
    let mut alignment = fit.alignment(turn.matrix() * fit.rotation);
    alignment.roll_from_orientations = true;
    Ok(alignment)
}

/// `σ_θ` in degrees: the standard error of the roll about the main axis that the positions
/// give (180 when they give none: a straight or single-point path).
pub(crate) fn roll_std_error_deg(fit: &Fit) -> f64 {
    let c = fit.scale_for(&fit.rotation);
    let stiffness = c * (fit.d.y + fit.s.z * fit.d.z);
    let residual = (fit.sigma_y - 2.0 * c * fit.d.dot(&fit.s) + c * c * fit.sigma_x).max(0.0);
    if fit.rank < 2 || stiffness <= f64::EPSILON * fit.d.x {
        return 180.0;
    }
    (residual / (3.0 * fit.n as f64 * stiffness))
        .sqrt()
        .to_degrees()
        .min(180.0)
}

/// The turn about `axis` (after `r0`) that best aligns the estimate's orientations with the
/// reference's, pose for pose.
fn orientation_roll(
    r0: &Matrix3<f64>,
    axis: &Unit<Vector3<f64>>,
    estimate: &Trajectory,
    reference: &Trajectory,
) -> f64 {
    let m: Matrix3<f64> = estimate
        .poses
        .iter()
        .zip(&reference.poses)
        .map(|(p, q)| {
            r0 * p.rotation.to_rotation_matrix().matrix()
                * q.rotation.to_rotation_matrix().matrix().transpose()
        })
        .sum();
    let a = axis.as_ref();
    let cos_part = m.trace() - a.dot(&(m * a));
    let sin_part = a.x * (m[(1, 2)] - m[(2, 1)])
        + a.y * (m[(2, 0)] - m[(0, 2)])
        + a.z * (m[(0, 1)] - m[(1, 0)]);
    sin_part.atan2(cos_part)
}

/// Umeyama alignment of `estimate`'s positions onto `reference`'s (pose-for-pose paired),
/// as evo's `traj_est.align(traj_ref)`; apply it with [`Alignment::apply_trajectory`].
///
/// One difference from evo: when the positions leave the rotation about the path's main
/// axis undetermined (a straight or nearly straight path), that rotation is taken from the
/// orientations instead of from the positions' noise (this module), and
/// [`Alignment::roll_from_orientations`] says so. Wherever the positions determine the
/// rotation the result is evo's.
pub fn align_trajectory(
    estimate: &Trajectory,
    reference: &Trajectory,
    with_scale: bool,
) -> Result<Alignment, EvalError> {
    let fit = Fit::new(&positions(estimate), &positions(reference), with_scale)?;
    resolve(&fit, estimate, reference)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::align::positions;
    use keylo_core::Pose;
    use nalgebra::{Isometry3, Translation3};

    /// A path along x with lateral wiggle `wiggle` and orientations turning slowly in yaw.
    fn path(n: usize, wiggle: f64) -> Trajectory {
        let mut t = Trajectory::default();
        for i in 0..n {
            let x = i as f64;
            let rot = UnitQuaternion::from_euler_angles(0.01 * x, -0.02 * x, 0.03 * x);
            let y = wiggle * (0.7 * x).sin();
            let z = wiggle * (1.3 * x).cos();
            t.push(x, Isometry3::from_parts(Translation3::new(x, y, z), rot));
        }
        t
    }

    fn moved(t: &Trajectory, by: &Pose, noise: f64) -> Trajectory {
        let mut out = Trajectory::default();
        for (i, (s, p)) in t.stamps.iter().zip(&t.poses).enumerate() {
            let e = noise * ((i * 7919 % 13) as f64 / 13.0 - 0.5);
            let jitter = Translation3::new(0.0, e, -e);
            out.push(*s, jitter * by * p);
        }
        out
    }

    fn align(est: &Trajectory, gt: &Trajectory) -> Alignment {
        let fit = Fit::new(&positions(est), &positions(gt), false).unwrap();
        resolve(&fit, est, gt).unwrap()
    }

    #[test]
    fn a_straight_noisy_path_takes_its_roll_from_the_orientations() {
        let gt = path(20, 0.0);
        let offset = Isometry3::from_parts(
            Translation3::new(2.0, -1.0, 0.5),
            UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1),
        );
        let est = moved(&gt, &offset, 0.02);
        let a = align(&est, &gt);
        assert!(a.roll_from_orientations);
        // The estimate is the reference moved rigidly, so the alignment undoes that motion.
        let undo = offset.rotation.inverse();
        assert!(a.rotation.angle_to(&undo).to_degrees() < 0.5, "{a:?}");
    }

    #[test]
    fn an_exactly_straight_path_is_aligned_instead_of_refused() {
        let gt = path(10, 0.0);
        let offset = Isometry3::rotation(Vector3::new(0.0, 0.0, 0.4));
        let a = align(&moved(&gt, &offset, 0.0), &gt);
        assert!(a.roll_from_orientations);
        assert!(a.rotation.angle_to(&offset.rotation.inverse()) < 1e-9);
    }

    #[test]
    fn a_path_that_fixes_its_roll_keeps_umeyamas_rotation() {
        let gt = path(20, 1.0);
        let offset = Isometry3::rotation(Vector3::new(0.2, 0.1, -0.3));
        let est = moved(&gt, &offset, 0.02);
        let fit = Fit::new(&positions(&est), &positions(&gt), false).unwrap();
        assert!(roll_std_error_deg(&fit) < MAX_ROLL_STD_ERROR_DEG);
        let a = resolve(&fit, &est, &gt).unwrap();
        assert!(!a.roll_from_orientations);
        assert_eq!(a, fit.alignment(fit.rotation));
    }

    #[test]
    fn the_closed_form_roll_beats_every_sampled_roll() {
        let gt = path(12, 0.0);
        let est = moved(&gt, &Isometry3::rotation(Vector3::new(0.5, 0.0, 0.0)), 0.01);
        let fit = Fit::new(&positions(&est), &positions(&gt), false).unwrap();
        let axis = Unit::new_normalize(fit.u.column(0).into_owned());
        let best = orientation_roll(&fit.rotation, &axis, &est, &gt);
        let score = |theta: f64| -> f64 {
            let r = UnitQuaternion::from_axis_angle(&axis, theta)
                .to_rotation_matrix()
                .matrix()
                * fit.rotation;
            est.poses
                .iter()
                .zip(&gt.poses)
                .map(|(p, q)| {
                    (q.rotation.to_rotation_matrix().matrix().transpose()
                        * r
                        * p.rotation.to_rotation_matrix().matrix())
                    .trace()
                })
                .sum()
        };
        for k in 0..360 {
            let theta = (k as f64).to_radians();
            assert!(score(best) >= score(theta) - 1e-9, "θ = {k}°");
        }
    }
}
