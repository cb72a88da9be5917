use keylo_core::CoreError;

/// Errors of the registration crate.
#[derive(Debug, thiserror::Error)]
pub enum RegistrationError {
    /// A parameter outside its valid range.
    #[error("`{field}` = {value}: {expected}")]
    BadParameter {
        field: &'static str,
        value: String,
        expected: String,
    },
    /// An input cloud the registrar cannot use.
    #[error("{0}")]
    BadCloud(String),
    /// The estimate left the plausible range; the registrar state is unchanged.
    #[error("{0}")]
    Diverged(String),
    /// An initial guess the solver cannot start from (non-finite).
    #[error("{0}")]
    BadGuess(String),
}

impl From<RegistrationError> for CoreError {
    fn from(e: RegistrationError) -> Self {
        match e {
            RegistrationError::BadParameter { .. } => CoreError::stage("registrar", e.to_string()),
            RegistrationError::BadCloud(m)
            | RegistrationError::Diverged(m)
            | RegistrationError::BadGuess(m) => CoreError::stage("registrar", m),
        }
    }
}

/// Checks `ok`, else a [`RegistrationError::BadParameter`].
pub(crate) fn check(
    ok: bool,
    field: &'static str,
    value: impl std::fmt::Debug,
    expected: &'static str,
) -> Result<(), RegistrationError> {
    if ok {
        Ok(())
    } else {
        Err(RegistrationError::BadParameter {
            field,
            value: format!("{value:?}"),
            expected: expected.to_string(),
        })
    }
}

/// Checks the `min_range`/`max_range` pair every registrar has: 0 < max ≤ 10 km,
/// 0 ≤ min < max.
pub(crate) fn check_range_limits(min_range: f64, max_range: f64) -> Result<(), RegistrationError> {
    check(
        max_range.is_finite() && max_range > 0.0 && max_range <= 1e4,
        "max_range",
        max_range,
        "expected 0 < max_range <= 10000 m",
    )?;
    check(
        min_range.is_finite() && min_range >= 0.0 && min_range < max_range,
        "min_range",
        min_range,
        "expected 0 <= min_range < max_range",
    )
}

/// Checks the guard and thread count every frame-to-map registrar has: `max_motion_per_frame`
/// ≥ 0 (0: no guard) and `max_num_threads` ≤ 1024 (0: automatic).
pub(crate) fn check_frame_step(
    max_motion_per_frame: f64,
    max_num_threads: usize,
) -> Result<(), RegistrationError> {
    check(
        max_motion_per_frame.is_finite() && max_motion_per_frame >= 0.0,
        "max_motion_per_frame",
        max_motion_per_frame,
        "expected 0 (no guard) or a positive distance in m",
    )?;
    check(
        max_num_threads <= 1024,
        "max_num_threads",
        max_num_threads,
        "expected 0 (automatic) ..= 1024",
    )
}

/// Checks the voxel map's settings KISS-ICP's map has: `max_points_per_voxel` in 1..=10000,
/// `min_motion_th` (the motion below which the threshold is not updated) in 0..=1000 m.
pub(crate) fn check_voxel_map(
    max_points_per_voxel: usize,
    min_motion_th: f64,
) -> Result<(), RegistrationError> {
    check(
        (1..=10_000).contains(&max_points_per_voxel),
        "max_points_per_voxel",
        max_points_per_voxel,
        "expected 1..=10000",
    )?;
    check(
        min_motion_th.is_finite() && (0.0..=1e3).contains(&min_motion_th),
        "min_motion_th",
        min_motion_th,
        "expected 0 <= min_motion_th <= 1000 m",
    )
}
