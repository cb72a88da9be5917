//! The SLAM hooks: motion prior, set pose, reset.

use super::handles::with;
use super::types::KeyloPipeline;
use crate::CapiError;

/// A row-major 4x4 rigid transform as a pose; an error naming `what` when it is not one.
fn rigid(m: &[f64; 16], what: &str) -> Result<keylo::Pose, CapiError> {
    keylo::rigid::pose_from_matrix(m)
        .map_err(|why| CapiError::Argument(format!("{what}: not a rigid transform ({why})")))
}

/// Reads 16 doubles from `m`.
///
/// # Safety
/// `m` is NULL or points to 16 readable doubles.
unsafe fn matrix_arg(m: *const f64, what: &str) -> Result<[f64; 16], CapiError> {
    if m.is_null() {
        return Err(CapiError::Argument(format!("{what} is NULL")));
    }
    let mut out = [0.0; 16];
    // SAFETY: 16 readable doubles per the contract.
    out.copy_from_slice(unsafe { std::slice::from_raw_parts(m, 16) });
    Ok(out)
}

/// SLAM hook: the motion from the last frame to the next (`matrix`: a row-major 4x4 rigid
/// transform, `last_pose⁻¹ · next_pose`, e.g. from an IMU) replaces the registrar's
/// constant-velocity model for the next frame only. Returns 0, or -1 when the matrix is not
/// rigid, the step is beyond `max_motion_per_frame`, or the registrar does not offer it.
///
/// # Safety
/// `matrix` NULL or pointing to 16 doubles.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_set_motion_prior(
    p: *mut KeyloPipeline,
    matrix: *const f64,
) -> i32 {
    with(p, |e| {
        // SAFETY: forwarded from the caller.
        let delta = rigid(&unsafe { matrix_arg(matrix, "matrix") }?, "motion prior")?;
        Ok(e.odometry_mut().set_motion_prior(&delta)?)
    })
}

/// SLAM hook: the last frame's pose becomes `matrix` (row-major 4x4 rigid transform); map
/// and motion are kept. Returns 0, or -1.
///
/// # Safety
/// `matrix` NULL or pointing to 16 doubles.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_set_pose(p: *mut KeyloPipeline, matrix: *const f64) -> i32 {
    with(p, |e| {
        // SAFETY: forwarded from the caller.
        let pose = rigid(&unsafe { matrix_arg(matrix, "matrix") }?, "pose")?;
        Ok(e.odometry_mut().set_pose(&pose)?)
    })
}

/// SLAM hook: forget the map, the motion and the last result; the next frame starts a new
/// trajectory at the identity. Returns 0, or -1.
///
/// # Safety
/// None beyond the rules in the header.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_reset(p: *mut KeyloPipeline) -> i32 {
    with(p, |e| e.reset())
}
