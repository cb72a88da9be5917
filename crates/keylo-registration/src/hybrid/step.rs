//! One Gauss–Newton step as a convex problem: minimise `½ uᵀHu + gᵀu` over the scaled twist
//! `u` inside the trust-region cone `‖u‖ ≤ r`, with `|vᵀ(a + u)| ≤ β` for every bounded weak
//! direction `v` (`a`: the correction made so far this frame), solved with Clarabel; plain
//! Gauss–Newton (clipped to the same region) when Clarabel fails or is not asked for.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT, SolverStatus,
    SupportedConeT,
};
use nalgebra::{Matrix6, Vector6};

/// Damping added to `H` (relative to its largest diagonal entry) so that the problem is
/// strictly convex even where neither cloud nor keypoints constrain it: there the step is 0.
const DAMPING: f64 = 1e-9;

/// The step problem.
#[derive(Debug, Clone)]
pub struct StepProblem<'a> {
    pub hessian: Matrix6<f64>,
    pub gradient: Vector6<f64>,
    /// Trust-region radius on `‖u‖`.
    pub radius: f64,
    /// Unit directions whose total correction is bounded by `bound`.
    pub bounded: &'a [Vector6<f64>],
    pub bound: f64,
    /// The correction so far.
    pub accumulated: Vector6<f64>,
}

/// How a step was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepSolver {
    Clarabel,
    /// Gauss–Newton, because Clarabel was not asked for or failed.
    GaussNewton,
}

/// The step and the solver that produced it; `None` for a non-finite or empty system.
pub fn solve(problem: &StepProblem, clarabel: bool) -> Option<(Vector6<f64>, StepSolver)> {
    let finite = problem
        .hessian
        .iter()
        .chain(problem.gradient.iter())
        .all(|v| v.is_finite());
    let scale = problem.hessian.diagonal().max();
    if !finite || scale <= 0.0 {
        return None;
    }
    if clarabel {
        if let Some(u) = solve_clarabel(problem, scale) {
            return Some((u, StepSolver::Clarabel));
        }
    }
    gauss_newton(problem, scale).map(|u| (u, StepSolver::GaussNewton))
}

/// `H / scale` (damped) as Clarabel's upper-triangular CSC matrix.
fn upper(h: &Matrix6<f64>, scale: f64) -> CscMatrix<f64> {
    let mut colptr = vec![0];
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    for c in 0..6 {
        for r in 0..=c {
            let mut v = 0.5 * (h[(r, c)] + h[(c, r)]) / scale;
            if r == c {
                v += DAMPING;
            }
            rowval.push(r);
            nzval.push(v);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(6, 6, colptr, rowval, nzval)
}

/// Constraint rows `A u + s = b`: two half-spaces per bounded direction, then the cone
/// `(r, u)`.
fn constraints(p: &StepProblem) -> (CscMatrix<f64>, Vec<f64>, Vec<SupportedConeT<f64>>) {
    let k = p.bounded.len();
    let rows = 2 * k + 7;
    let mut dense = vec![vec![0.0; 6]; rows];
    let mut b = vec![0.0; rows];
    for (i, v) in p.bounded.iter().enumerate() {
        let va = v.dot(&p.accumulated);
        for j in 0..6 {
            dense[2 * i][j] = v[j];
            dense[2 * i + 1][j] = -v[j];
        }
        b[2 * i] = p.bound - va;
        b[2 * i + 1] = p.bound + va;
    }
    b[2 * k] = p.radius;
    for j in 0..6 {
        dense[2 * k + 1 + j][j] = -1.0;
    }
    let mut cones = Vec::new();
    if k > 0 {
        cones.push(NonnegativeConeT(2 * k));
    }
    cones.push(SecondOrderConeT(7));
    let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
    for j in 0..6 {
        for (r, row) in dense.iter().enumerate() {
            if row[j] != 0.0 {
                rowval.push(r);
                nzval.push(row[j]);
            }
        }
        colptr.push(rowval.len());
    }
    (CscMatrix::new(rows, 6, colptr, rowval, nzval), b, cones)
}

fn solve_clarabel(p: &StepProblem, scale: f64) -> Option<Vector6<f64>> {
    let hessian = upper(&p.hessian, scale);
    let q: Vec<f64> = p.gradient.iter().map(|v| v / scale).collect();
    let (a, b, cones) = constraints(p);
    let settings = DefaultSettings {
        verbose: false,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&hessian, &q, &a, &b, &cones, settings).ok()?;
    solver.solve();
    let ok = matches!(
        solver.solution.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    );
    let u = Vector6::from_iterator(solver.solution.x.iter().copied());
    (ok && u.iter().all(|v| v.is_finite())).then_some(u)
}

/// `−H⁻¹g` (damped), its components along the bounded directions clipped to their bounds,
/// then scaled into the trust region.
fn gauss_newton(p: &StepProblem, scale: f64) -> Option<Vector6<f64>> {
    let h = p.hessian / scale + Matrix6::identity() * DAMPING;
    let mut u = h.cholesky()?.solve(&(-p.gradient / scale));
    for v in p.bounded {
        let (va, vu) = (v.dot(&p.accumulated), v.dot(&u));
        let clipped = (va + vu).clamp(-p.bound, p.bound) - va;
        u += v * (clipped - vu);
    }
    let n = u.norm();
    if n > p.radius {
        u *= p.radius / n;
    }
    u.iter().all(|v| v.is_finite()).then_some(u)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(bounded: &[Vector6<f64>]) -> StepProblem<'_> {
        StepProblem {
            hessian: Matrix6::from_diagonal(&Vector6::new(4.0, 4.0, 4.0, 1.0, 1.0, 1.0)),
            gradient: Vector6::new(-0.4, 0.8, 0.0, 0.1, 0.0, -0.2),
            radius: 10.0,
            bounded,
            bound: 0.05,
            accumulated: Vector6::zeros(),
        }
    }

    #[test]
    fn unconstrained_step_is_gauss_newton() {
        let expected = Vector6::new(0.1, -0.2, 0.0, -0.1, 0.0, 0.2);
        for clarabel in [true, false] {
            let (u, how) = solve(&problem(&[]), clarabel).unwrap();
            assert!((u - expected).norm() < 1e-6, "{u} ({how:?})");
        }
        assert_eq!(solve(&problem(&[]), true).unwrap().1, StepSolver::Clarabel);
    }

    #[test]
    fn trust_region_and_weak_bounds_hold() {
        let x = Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let (u, _) = solve(&problem(&[x]), true).unwrap();
        assert!((u[0] - 0.05).abs() < 1e-6, "{u}");
        assert!((u[1] + 0.2).abs() < 1e-6, "{u}");
        let mut small = problem(&[]);
        small.radius = 0.01;
        for clarabel in [true, false] {
            let (u, _) = solve(&small, clarabel).unwrap();
            assert!(u.norm() <= 0.01 + 1e-7, "{u}");
        }
    }

    #[test]
    fn a_flat_direction_does_not_move() {
        let mut p = problem(&[]);
        p.hessian[(0, 0)] = 0.0;
        p.gradient[0] = 0.0;
        let (u, _) = solve(&p, true).unwrap();
        assert!(u[0].abs() < 1e-6, "{u}");
    }
}
