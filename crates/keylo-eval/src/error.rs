//! The crate's single error type.

/// Everything that can go wrong while computing metrics (trajectory files are read by
/// `keylo_io::trajectory`).
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// Association found no pair of stamps within the allowed difference.
    #[error(
        "found no matching timestamps between {reference} and {estimate} \
         with max. time diff {max_diff} s and time offset {offset} s"
    )]
    NoMatches {
        /// Reference label.
        reference: String,
        /// Estimate label.
        estimate: String,
        /// Allowed stamp difference, seconds.
        max_diff: f64,
        /// Offset added to the estimate's stamps, seconds.
        offset: f64,
    },
    /// Two trajectories that must be pose-for-pose paired differ in length.
    #[error("{reference} has {reference_len} poses but {estimate} has {estimate_len}")]
    LengthMismatch {
        /// Reference label.
        reference: String,
        /// Its length.
        reference_len: usize,
        /// Estimate label.
        estimate: String,
        /// Its length.
        estimate_len: usize,
    },
    /// Umeyama alignment needs at least 3 point pairs.
    #[error("alignment needs at least 3 point pairs, got {found}")]
    TooFewPoints {
        /// Points given.
        found: usize,
    },
    /// Umeyama alignment on (nearly) collinear or coincident points.
    #[error("degenerate covariance rank ({rank} of 3), Umeyama alignment is not possible")]
    Degenerate {
        /// Number of singular values above machine epsilon.
        rank: usize,
    },
    /// The chosen delta selects no pose pair.
    #[error(
        "delta = {delta} produced an empty list of pose pairs ({poses} poses); try a lower value"
    )]
    NoPairs {
        /// Human-readable delta, e.g. "10 m".
        delta: String,
        /// Number of poses.
        poses: usize,
    },
    /// No segment of the requested lengths fits into the trajectory.
    #[error("no drift segment fits: path is {path_length:.3} m, shortest segment {shortest:.3} m")]
    NoSegments {
        /// Reference path length, metres.
        path_length: f64,
        /// Shortest requested segment, metres.
        shortest: f64,
    },
    /// An option has an invalid value.
    #[error("invalid option {name}: {reason}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// Why it is invalid.
        reason: String,
    },
}
