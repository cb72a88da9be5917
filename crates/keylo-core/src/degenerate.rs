//! Degenerate frames: frames whose registration cannot constrain all six degrees of freedom,
//! so that (part of) their pose is the motion model's prediction, not odometry.
//!
//! A frame is degenerate when the registrar used fewer points than its documented minimum
//! ([`crate::Registrar::min_points`]), or when its degeneracy analysis finds a direction
//! with no information: an eigenvalue of the 6×6 information matrix at most
//! [`NO_INFORMATION_RATIO`] times the largest (every point on one plane leaves three such
//! directions for point-to-plane residuals). Weak but informed directions
//! (`degeneracy.weak_ratio`) are reported in degeneracy.csv, not here.

use serde::Serialize;

use crate::Degeneracy;

/// The registered points below which a registrar's pose is not constrained, unless it says
/// otherwise ([`crate::Registrar::min_points`]): six, one per degree of freedom, as for
/// point-to-plane and distribution residuals of one constraint each.
pub const DEFAULT_MIN_POINTS: usize = 6;

/// An eigenvalue at most this fraction of the largest carries no information (rounding
/// error of an exactly zero one).
pub const NO_INFORMATION_RATIO: f64 = 1e-9;

/// Why a frame is degenerate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "reason", rename_all = "kebab-case")]
pub enum Degenerate {
    /// The registrar used `points`, fewer than its `minimum`.
    TooFewPoints { points: usize, minimum: usize },
    /// The degeneracy analysis found `directions` directions with no information.
    NoInformation { directions: usize },
}

impl Degenerate {
    /// The verdict on a frame registered with `points` points by a registrar needing
    /// `minimum`, with its degeneracy analysis if it made one.
    pub fn of(points: usize, minimum: usize, analysis: Option<&Degeneracy>) -> Option<Self> {
        if points < minimum {
            return Some(Self::TooFewPoints { points, minimum });
        }
        let d = analysis?;
        let largest = d.eigenvalues.iter().copied().fold(0.0f64, f64::max);
        let directions = if largest > 0.0 && largest.is_finite() {
            d.eigenvalues
                .iter()
                .filter(|&&e| e.is_nan() || e <= NO_INFORMATION_RATIO * largest)
                .count()
        } else {
            6
        };
        (directions > 0).then_some(Self::NoInformation { directions })
    }

    /// The short name of the reason (`too-few-points`, `no-information`), as in frames.csv.
    pub fn label(&self) -> &'static str {
        match self {
            Self::TooFewPoints { .. } => "too-few-points",
            Self::NoInformation { .. } => "no-information",
        }
    }

    /// The reason in words, for messages.
    pub fn describe(&self) -> String {
        match *self {
            Self::TooFewPoints { points, minimum } => format!(
                "{points} registered point{}, fewer than the {minimum} the registrar needs to \
                 constrain six degrees of freedom; its pose is the motion model's prediction",
                if points == 1 { "" } else { "s" }
            ),
            Self::NoInformation { directions } => format!(
                "the geometry gives no information along {directions} of the six pose \
                 directions (degeneracy analysis); along those its pose is the prediction"
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn analysis(eigenvalues: [f64; 6]) -> Degeneracy {
        Degeneracy {
            eigenvalues,
            eigenvectors: [[0.0; 6]; 6],
            condition: f64::INFINITY,
            weak: 0,
            length_scale: 1.0,
            residuals: 100,
        }
    }

    #[test]
    fn too_few_points_comes_first() {
        let d = Degenerate::of(1, 6, None).unwrap();
        assert_eq!(
            d,
            Degenerate::TooFewPoints {
                points: 1,
                minimum: 6
            }
        );
        assert!(d
            .describe()
            .starts_with("1 registered point, fewer than the 6"));
        assert_eq!(Degenerate::of(6, 6, None), None);
    }

    #[test]
    fn a_direction_without_information_is_degenerate_a_weak_one_is_not() {
        let plane = analysis([1e-18, 0.0, 2e-17, 4.0, 5.0, 9.0]);
        assert_eq!(
            Degenerate::of(500, 6, Some(&plane)),
            Some(Degenerate::NoInformation { directions: 3 })
        );
        let weak = analysis([1e-4, 1.0, 2.0, 4.0, 5.0, 9.0]);
        assert_eq!(Degenerate::of(500, 6, Some(&weak)), None);
        let empty = analysis([0.0; 6]);
        assert_eq!(
            Degenerate::of(500, 6, Some(&empty)),
            Some(Degenerate::NoInformation { directions: 6 })
        );
    }

    #[test]
    fn it_serialises_with_its_reason() {
        let d = Degenerate::TooFewPoints {
            points: 1,
            minimum: 3,
        };
        let json = serde_json::to_string(&d).unwrap();
        assert_eq!(
            json,
            r#"{"reason":"too-few-points","points":1,"minimum":3}"#
        );
    }
}
