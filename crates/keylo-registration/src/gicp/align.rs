//! GICP's outer loop with PCL's semantics (`GeneralizedIterativeClosestPoint::
//! computeTransformation`): each iteration pairs every source point with its nearest target
//! point within `max_correspondence_distance`, weighs the pair by `(C_t + R C_s Rᵀ)⁻¹` at the
//! current rotation, and minimises the plane-to-plane cost over those pairs ([`solve`]);
//! it stops when one iteration changes no rotation entry by `rotation_epsilon` and no other
//! entry of the 4×4 transform by `transformation_epsilon`, or after `max_iterations`.

use nalgebra::{Isometry3, Point3};
use rayon::prelude::*;

use super::covariances::{patches, Indexed, Patch};
use super::solve::{minimise, Pair};
use crate::RegistrationError;

/// Settings of one alignment (PCL's names and defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GicpSettings {
    /// Pairs farther apart than this are not used (PCL 5 m).
    pub max_correspondence_distance: f64,
    /// Outer iterations at most (PCL 200).
    pub max_iterations: usize,
    /// Converged when no translation entry changes by this (PCL 5e-4).
    pub transformation_epsilon: f64,
    /// … and no rotation entry by this (PCL 2e-3).
    pub rotation_epsilon: f64,
    /// The cost: plane-to-plane (GICP) or point-to-plane.
    pub cost: Cost,
    /// `Some(c)`: converged instead when an iteration's motion (twist norm, KISS-ICP's
    /// `convergence_criterion`) is below `c`; the epsilons above are then unused.
    pub step_convergence: Option<f64>,
    /// KISS-ICP's Geman–McClure kernel scale κ (m): pairs are down-weighted by
    /// `(κ / (κ + |r|²))²`; `None`: every pair counts fully (PCL).
    pub kernel: Option<f64>,
    /// Gauss–Newton steps per pairing at most: [`super::solve::MAX_STEPS`] solves each
    /// pairing to its minimum (PCL); 1 re-pairs after every step (KISS-ICP).
    pub steps_per_pairing: usize,
}

impl Default for GicpSettings {
    fn default() -> Self {
        Self {
            max_correspondence_distance: 5.0,
            max_iterations: 200,
            transformation_epsilon: 5e-4,
            rotation_epsilon: 2e-3,
            cost: Cost::Gicp,
            kernel: None,
            step_convergence: None,
            steps_per_pairing: super::solve::MAX_STEPS,
        }
    }
}

/// What a pair's residual is weighed by.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Cost {
    /// `(C_t + R C_s Rᵀ)⁻¹`: plane-to-plane (Segal et al.).
    #[default]
    Gicp,
    /// `n nᵀ` with `n` the target point's normal (its covariance's smallest direction).
    PointToPlane,
}

/// A cloud ready to be a GICP target or source: its points, tree and patches (covariance and
/// normal of each point).
pub struct GicpCloud {
    pub cloud: Indexed,
    pub patches: Vec<Patch>,
}

impl GicpCloud {
    /// Points with covariances from `k` neighbours regularised with `epsilon`.
    pub fn new(
        points: Vec<Point3<f64>>,
        k: usize,
        epsilon: f64,
    ) -> Result<Self, RegistrationError> {
        check_size(points.len())?;
        let cloud = Indexed::new(points)?;
        let patches = patches(&cloud, k, epsilon);
        Ok(Self { cloud, patches })
    }

    pub fn len(&self) -> usize {
        self.cloud.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cloud.points.is_empty()
    }
}

/// Covariances need a few points.
pub(crate) fn check_size(n: usize) -> Result<(), RegistrationError> {
    if n < MIN_POINTS {
        return Err(RegistrationError::BadCloud(format!(
            "GICP needs at least {MIN_POINTS} points for covariances, the cloud has {n}"
        )));
    }
    Ok(())
}

/// Points below which a cloud cannot be registered (covariances, six degrees of freedom).
pub const MIN_POINTS: usize = 6;

/// A target point paired with a source point.
#[derive(Debug, Clone, Copy)]
pub struct Neighbour {
    pub point: Point3<f64>,
    pub patch: Patch,
}

/// Where source points find their nearest target point.
pub trait Target: Sync {
    /// The nearest target point to `q` closer than `sqrt(max_d2)`.
    fn nearest(&self, q: &Point3<f64>, max_d2: f64) -> Option<Neighbour>;

    /// Appends to `out` the target points closer than `radius` to `q` (for the degeneracy
    /// analysis' plane fits).
    fn points_within(&self, q: &Point3<f64>, radius: f64, out: &mut Vec<Point3<f64>>);
}

impl Target for GicpCloud {
    fn nearest(&self, q: &Point3<f64>, max_d2: f64) -> Option<Neighbour> {
        let (j, d2) = self.cloud.nearest(q);
        (d2 < max_d2).then(|| Neighbour {
            point: self.cloud.points[j],
            patch: self.patches[j],
        })
    }

    fn points_within(&self, q: &Point3<f64>, radius: f64, out: &mut Vec<Point3<f64>>) {
        let mut hits = Vec::new();
        self.cloud.tree.within(q, radius, &mut hits);
        out.extend(hits.iter().map(|&i| self.cloud.points[i as usize]));
    }
}

/// The outcome of one alignment.
#[derive(Debug, Clone, PartialEq)]
pub struct GicpResult {
    /// The pose taking source points into the target frame.
    pub pose: Isometry3<f64>,
    /// Outer iterations run.
    pub iterations: usize,
    /// Whether the epsilon rule stopped the loop (false: the iteration cap did).
    pub converged: bool,
    /// The last iteration's pairs (source points moved by the guess).
    pub pairs: Vec<Pair>,
}

/// Aligns `source` (points and their patches, source frame) to `target` from `guess`,
/// as PCL's `align(output, guess)`.
pub fn align(
    (points, patches): (&[Point3<f64>], &[Patch]),
    target: &impl Target,
    guess: &Isometry3<f64>,
    settings: &GicpSettings,
) -> Result<GicpResult, RegistrationError> {
    if !keylo_core::rigid::is_finite(guess) {
        return Err(RegistrationError::BadGuess(format!(
            "GICP initial guess is not finite: {guess}"
        )));
    }
    let max_d2 = settings.max_correspondence_distance.powi(2);
    // As PCL: the source moved by the guess once; the loop estimates the transform `rel`
    // on top of it, and its convergence rule measures `rel`'s changes.
    let moved: Vec<Point3<f64>> = points.iter().map(|p| guess * p).collect();
    let mut rel = Isometry3::identity();
    let mut iterations = 0;
    let mut converged = false;
    let mut pairs = Vec::new();
    while !converged {
        let rotation = (rel * guess).rotation.to_rotation_matrix().into_inner();
        pairs = (0..moved.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .filter_map(|i| {
                let p = moved[i];
                let n = target.nearest(&(rel * p), max_d2)?;
                let weight = match settings.cost {
                    Cost::Gicp => {
                        let c = rotation * patches[i].covariance * rotation.transpose()
                            + n.patch.covariance;
                        c.try_inverse()?
                    }
                    Cost::PointToPlane => n.patch.normal * n.patch.normal.transpose(),
                };
                Some(Pair {
                    source: p,
                    target: n.point,
                    weight,
                })
            })
            .collect();
        if pairs.len() < MIN_POINTS {
            return Err(RegistrationError::Diverged(format!(
                "GICP: {} of {} source points have a target point within {} m; too few to \
                 register",
                pairs.len(),
                moved.len(),
                settings.max_correspondence_distance
            )));
        }
        let next = minimise(&pairs, &rel, settings.kernel, settings.steps_per_pairing);
        iterations += 1;
        converged = match settings.step_convergence {
            Some(c) => crate::se3::log(&(next * rel.inverse())).norm() < c,
            None => largest_change(&rel, &next, settings) < 1.0,
        };
        rel = next;
        if iterations >= settings.max_iterations {
            break;
        }
    }
    let mut pose = rel * guess;
    pose.rotation.renormalize();
    if !pose.translation.vector.iter().all(|v| v.is_finite()) {
        return Err(RegistrationError::Diverged(
            "GICP produced a non-finite pose".into(),
        ));
    }
    Ok(GicpResult {
        pose,
        iterations,
        converged,
        pairs,
    })
}

/// Source points per parallel work item when pairing (the order of the pairs does not
/// depend on the number of threads).
const CHUNK: usize = 256;

/// PCL's convergence measure: the largest change of a 4×4 entry, rotation entries over
/// `rotation_epsilon`, the others over `transformation_epsilon` (below 1: converged).
fn largest_change(a: &Isometry3<f64>, b: &Isometry3<f64>, s: &GicpSettings) -> f64 {
    let (ma, mb) = (a.to_homogeneous(), b.to_homogeneous());
    let mut delta = 0.0f64;
    for r in 0..4 {
        for c in 0..4 {
            let scale = if r < 3 && c < 3 {
                s.rotation_epsilon
            } else {
                s.transformation_epsilon
            };
            delta = delta.max((ma[(r, c)] - mb[(r, c)]).abs() / scale);
        }
    }
    delta
}
