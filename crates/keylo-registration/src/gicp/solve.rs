//! The inner problem of one GICP iteration: with the pairs and their weights fixed, the rigid
//! transform minimising `Σ rᵀ W r`, `r = T p − q`, by Gauss–Newton on left perturbations
//! `T ← exp([ρ, φ]) T` (PCL minimises the same cost with BFGS over x y z roll pitch yaw; the
//! minimum is the same).

use nalgebra::{Isometry3, Matrix3, Matrix6, Point3, Vector6};
use std::ops::AddAssign;

use rayon::prelude::*;

use crate::se3;

/// One source point (already moved by the guess), its target point and the pair's weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair {
    pub source: Point3<f64>,
    pub target: Point3<f64>,
    pub weight: Matrix3<f64>,
}

/// Gauss–Newton steps at most per iteration when solving to the minimum (PCL's BFGS: 20).
pub const MAX_STEPS: usize = 20;
/// A step shorter than this (twist norm) ends the inner solve.
const STEP_TOLERANCE: f64 = 1e-10;

/// The transform minimising the pairs' cost from `start` (Gauss–Newton to a step below
/// [`STEP_TOLERANCE`], at most `max_steps` steps: [`MAX_STEPS`] to solve each pairing to its
/// minimum as PCL does, 1 to take one step per pairing as KISS-ICP does). PCL's BFGS instead
/// stops once the mean cost's gradient is below 0.01 (its gradient tolerances), an absolute
/// threshold whose
/// meaning changes with the cost's scale (point-to-plane and robust-kernel costs are far
/// smaller than plane-to-plane ones); on PCL's own parity pairs solving to the minimum changes
/// the pose by < 0.1 mm (docs/results/gicp.md).
///
/// With `kernel` κ each pair's weight is scaled by KISS-ICP's Geman–McClure factor
/// `(κ / (κ + |r|²))²` at the current residual, so pairs far apart (wrong pairs after a fast
/// turn) lose their pull.
pub fn minimise(
    pairs: &[Pair],
    start: &Isometry3<f64>,
    kernel: Option<f64>,
    max_steps: usize,
) -> Isometry3<f64> {
    let mut t = *start;
    for _ in 0..max_steps {
        let (h, g) = normal_equations(pairs, &t, kernel);
        let Some(step) = h.cholesky().map(|c| c.solve(&(-g))) else {
            break;
        };
        if !step.iter().all(|v| v.is_finite()) {
            break;
        }
        t = se3::exp(&step) * t;
        // Products of unit quaternions drift off unit length by rounding; the odometry's
        // `last⁻¹ · pose` (a conjugate, exact only for unit length) would amplify the drift
        // about 2.4× a frame until the poses shear (issue 47).
        t.rotation.renormalize();
        if step.norm() < STEP_TOLERANCE {
            break;
        }
    }
    t
}

/// Pairs per parallel work item; partial sums are added in chunk order, so the result does
/// not depend on the number of threads.
const CHUNK: usize = 512;

/// `JᵀWJ` and `JᵀWr` summed over the pairs at `t` (J: ∂r/∂[ρ, φ] = [I, −[Tp]×]).
fn normal_equations(
    pairs: &[Pair],
    t: &Isometry3<f64>,
    kernel: Option<f64>,
) -> (Matrix6<f64>, Vector6<f64>) {
    let zero = (Matrix6::zeros(), Vector6::zeros());
    let partials: Vec<(Matrix6<f64>, Vector6<f64>)> = pairs
        .par_chunks(CHUNK)
        .map(|chunk| {
            chunk.iter().fold(zero, |(mut h, mut g), pair| {
                let moved = t * pair.source;
                let r = moved - pair.target;
                let robust = kernel.map_or(1.0, |k| (k / (k + r.norm_squared())).powi(2));
                let w = &(pair.weight * robust);
                let skew = -moved.coords.cross_matrix();
                // J = [I | skew]; JᵀW = [W ; skewᵀ W].
                let wr = w * r;
                let sw = skew.transpose() * w;
                let mut block = |i: usize, j: usize, m: &Matrix3<f64>| {
                    h.fixed_view_mut::<3, 3>(i, j).add_assign(m);
                };
                block(0, 0, w);
                block(0, 3, &(w * skew));
                block(3, 0, &(sw));
                block(3, 3, &(sw * skew));
                g.fixed_rows_mut::<3>(0).add_assign(&wr);
                g.fixed_rows_mut::<3>(3)
                    .add_assign(&(skew.transpose() * wr));
                (h, g)
            })
        })
        .collect();
    partials.iter().fold(zero, |a, b| (a.0 + b.0, a.1 + b.1))
}
