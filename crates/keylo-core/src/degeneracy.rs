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

    /// The pose covariance `σ² H⁻¹` of the registration, in twist coordinates `[ρ, φ]`
    /// (metres, radians; a world-frame perturbation, as the matrix), for residuals of
    /// standard deviation `sigma` metres (e.g. the sensor's range noise, ~0.03 m for an
    /// Ouster OS0). `None` when the matrix is singular (some eigenvalue not positive): a
    /// fully unconstrained direction has no finite covariance.
    ///
    /// ```
    /// use keylo_core::Degeneracy;
    /// // Per-residual information 4 along every scaled axis, 100 residuals, L = 10 m.
    /// let mut eigenvectors = [[0.0; 6]; 6];
    /// for (i, v) in eigenvectors.iter_mut().enumerate() { v[i] = 1.0; }
    /// let d = Degeneracy { eigenvalues: [4.0; 6], eigenvectors, condition: 1.0, weak: 0,
    ///                      length_scale: 10.0, residuals: 100 };
    /// let c = d.covariance(0.02).unwrap();
    /// assert!((c[0][0] - 0.02f64.powi(2) / 400.0).abs() < 1e-15); // translation, m²
    /// assert!((c[5][5] - 0.02f64.powi(2) / 400.0 / 100.0).abs() < 1e-15); // rotation, rad²
    /// ```
    pub fn covariance(&self, sigma: f64) -> Option<[[f64; 6]; 6]> {
        if self.residuals == 0
            || self
                .eigenvalues
                .iter()
                .any(|&l| !(l > 0.0 && l.is_finite()))
        {
            return None;
        }
        let inv_l = 1.0 / self.length_scale.max(1e-9);
        let scale = |i: usize| if i < 3 { 1.0 } else { inv_l };
        let factor = sigma * sigma / self.residuals as f64;
        let mut cov = [[0.0; 6]; 6];
        for (i, row) in cov.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                let sum: f64 = (0..6)
                    .map(|k| {
                        let v = &self.eigenvectors[k];
                        v[i] * v[j] / self.eigenvalues[k]
                    })
                    .sum();
                *c = factor * scale(i) * scale(j) * sum;
            }
        }
        Some(cov)
    }

    /// Whether some direction is weak.
    pub fn is_degenerate(&self) -> bool {
        self.weak > 0
    }
}
