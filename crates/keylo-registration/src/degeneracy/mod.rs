//! Degeneracy detection: the eigen-structure of a registration's 6×6 information matrix,
//! scale-aware (rotations scaled by the RMS range), per residual. [`analyse`] turns a matrix
//! into a [`Degeneracy`]; [`plane_information`] builds the point-to-plane matrix of a cloud
//! against a voxel map, which shows what point-to-point ICP's own matrix cannot (its
//! translation block is the identity times the point count whatever the geometry).
//!
//! ```
//! use keylo_registration::degeneracy::analyse;
//! use nalgebra::Matrix6;
//! // Information along every axis except x.
//! let info = Matrix6::from_diagonal(&nalgebra::Vector6::new(0.0, 1.0, 1.0, 1.0, 1.0, 1.0));
//! let d = analyse(&info, 1, 1.0, 0.01);
//! assert_eq!(d.weak, 1);
//! assert!((d.weak_directions()[0][0].abs() - 1.0).abs() < 1e-12);
//! ```

mod plane_info;

pub use plane_info::{information_with_normals, plane_information, PlaneInformation};
pub(crate) use plane_info::{normals_of, planar_normal_of, plane_information_with, plane_normal};

use keylo_core::Degeneracy;
use nalgebra::{Matrix6, Vector6};
use serde::{Deserialize, Serialize};

use crate::error::check;
use crate::RegistrationError;

/// `[registrar.degeneracy]`: the per-frame degeneracy analysis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct DegeneracyConfig {
    /// Analyse every frame (eigenvalues, condition number, weak directions in the output).
    pub analyse: bool,
    /// A direction is weak when its eigenvalue is below this fraction of the largest.
    pub weak_ratio: f64,
    /// Points (an even stride over the registered cloud) the analysis looks at.
    pub max_points: usize,
}

impl Default for DegeneracyConfig {
    fn default() -> Self {
        Self {
            analyse: true,
            weak_ratio: 0.005,
            max_points: 2000,
        }
    }
}

impl DegeneracyConfig {
    pub(crate) fn validate(&self) -> Result<(), RegistrationError> {
        check(
            self.weak_ratio.is_finite() && self.weak_ratio > 0.0 && self.weak_ratio < 1.0,
            "degeneracy.weak_ratio",
            self.weak_ratio,
            "expected 0 < weak_ratio < 1",
        )?;
        check(
            (10..=1_000_000).contains(&self.max_points),
            "degeneracy.max_points",
            self.max_points,
            "expected 10..=1000000",
        )
    }
}

/// `S = diag(1, 1, 1, 1/L, 1/L, 1/L)`: twist coordinates `[ρ, φ]` from scaled ones
/// `[ρ, L·φ]` (`δ = S·u`).
pub fn scaling(length_scale: f64) -> Vector6<f64> {
    let inv = 1.0 / length_scale.max(1e-9);
    Vector6::new(1.0, 1.0, 1.0, inv, inv, inv)
}

/// The matrix in scaled coordinates: `S·H·S`.
pub fn scaled(info: &Matrix6<f64>, length_scale: f64) -> Matrix6<f64> {
    let s = Matrix6::from_diagonal(&scaling(length_scale));
    s * info * s
}

/// Ascending eigenvalues and unit eigenvectors (columns) of a symmetric matrix, each vector's
/// largest component made positive so the output is reproducible.
pub fn sorted_eigen(m: &Matrix6<f64>) -> (Vector6<f64>, Matrix6<f64>) {
    let sym = (m + m.transpose()) * 0.5;
    let e = sym.symmetric_eigen();
    let mut order: Vec<usize> = (0..6).collect();
    order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    let mut values = Vector6::zeros();
    let mut vectors = Matrix6::zeros();
    for (k, &i) in order.iter().enumerate() {
        values[k] = e.eigenvalues[i];
        let mut v = e.eigenvectors.column(i).into_owned();
        let lead = v.iamax();
        if v[lead] < 0.0 {
            v = -v;
        }
        vectors.set_column(k, &v);
    }
    (values, vectors)
}

/// The [`Degeneracy`] of `info` (twist `[ρ, φ]`, summed over `residuals` residuals), with
/// rotations scaled by `length_scale` and weak directions below `weak_ratio × λ_max`.
pub fn analyse(
    info: &Matrix6<f64>,
    residuals: usize,
    length_scale: f64,
    weak_ratio: f64,
) -> Degeneracy {
    let per = scaled(info, length_scale) / residuals.max(1) as f64;
    let (values, vectors) = sorted_eigen(&per);
    let largest = values[5];
    let smallest = values[0];
    let condition = if smallest > 0.0 {
        largest / smallest
    } else {
        f64::INFINITY
    };
    let weak = if largest > 0.0 {
        values
            .iter()
            .take_while(|&&v| v < weak_ratio * largest)
            .count()
    } else {
        6
    };
    let mut eigenvectors = [[0.0; 6]; 6];
    for (k, row) in eigenvectors.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = vectors[(j, k)];
        }
    }
    Degeneracy {
        eigenvalues: values.into(),
        eigenvectors,
        condition,
        weak,
        length_scale,
        residuals,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_is_scaled_by_the_length() {
        // 100 per rad of rotation about z at L = 10 m is 1 per metre of motion.
        let info = Matrix6::from_diagonal(&Vector6::new(1.0, 1.0, 1.0, 1.0, 1.0, 100.0));
        let d = analyse(&info, 1, 10.0, 0.05);
        assert!((d.eigenvalues[5] - 1.0).abs() < 1e-12);
        assert!((d.eigenvalues[0] - 0.01).abs() < 1e-12);
        assert_eq!(d.weak, 2);
        assert!((d.condition - 100.0).abs() < 1e-9);
    }

    #[test]
    fn zero_matrix_is_all_weak() {
        let d = analyse(&Matrix6::zeros(), 0, 1.0, 0.01);
        assert_eq!(d.weak, 6);
        assert!(d.condition.is_infinite());
    }
}
