//! How well the geometry constrains a registration: the eigen-structure of the normal
//! equations at convergence, as a registrar reports it in [`crate::Registration`].

use serde::Serialize;

/// Eigen-analysis of a registration's 6×6 information matrix at convergence (keylo's
/// registrars: the point-to-plane `JᵀJ` of the aligned cloud against their map).
///
/// Coordinates are the twist `[tx, ty, tz, L·rx, L·ry, L·rz]` of a world-frame perturbation:
/// rotations are scaled by the length `L` (`length_scale`, the RMS range of the points) so
/// that a unit in either block moves a typical point by about a metre, and the matrix is
/// divided by the number of residuals (information per point).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Degeneracy {
    /// Eigenvalues, ascending.
    pub eigenvalues: [f64; 6],
    /// Unit eigenvectors, `eigenvectors[i]` belonging to `eigenvalues[i]`.
    pub eigenvectors: [[f64; 6]; 6],
    /// Largest over smallest eigenvalue (infinite when the smallest is not positive).
    pub condition: f64,
    /// How many of the smallest eigenvalues lie below `weak_ratio × largest`: the directions
    /// `eigenvectors[..weak]` are the weak (unconstrained) ones.
    pub weak: usize,
    /// The rotation scale `L`, metres.
    pub length_scale: f64,
    /// Residuals the matrix sums over.
    pub residuals: usize,
}

impl Degeneracy {
    /// The weak directions, weakest first.
    pub fn weak_directions(&self) -> &[[f64; 6]] {
        &self.eigenvectors[..self.weak.min(6)]
    }

    /// Whether some direction is weak.
    pub fn is_degenerate(&self) -> bool {
        self.weak > 0
    }
}
