//! Results out: statistics, pose, degeneracy, covariance, the registered cloud, the local map.

use keylo::{Degenerate, FrameResult};

use super::handles::with;
use super::sized::write_out;
use super::types::{
    KeyloDegeneracy, KeyloFrameStats, KeyloPipeline, KeyloPose, KEYLO_CAPI_NOT_ANALYSED,
    KEYLO_CAPI_OK, KEYLO_DEGENERATE_NONE, KEYLO_DEGENERATE_NO_INFORMATION,
    KEYLO_DEGENERATE_TOO_FEW_POINTS,
};
use crate::{CapiError, Embedded};

/// A count as `u32`, saturating.
fn saturate(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// The last frame's result, or an error before the first frame.
fn last(e: &Embedded) -> Result<&FrameResult, CapiError> {
    e.last()
        .map(|o| &o.result)
        .ok_or_else(|| CapiError::Argument("no frame processed yet".into()))
}

/// Writes the last frame's statistics to `out` (its `size` set by the caller; at least the
/// bytes up to and including `frame`). Returns 0, or -1 before the first frame or when `size`
/// is too small.
///
/// # Safety
/// `out` NULL or pointing to `out->size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_stats(
    p: *mut KeyloPipeline,
    out: *mut KeyloFrameStats,
) -> i32 {
    with(p, |e| {
        let r = last(e)?;
        let ms = |s: f64| 1e3 * s;
        let stats = KeyloFrameStats {
            size: 0,
            frame: r.index,
            keypoints: r.keypoints as u64,
            cloud_points: r.cloud_points as u64,
            registered_points: r.registered_points as u64,
            map_points: r.map_points as u64,
            iterations: r.iterations as u64,
            converged: r.converged,
            image_ms: ms(r.timings.image),
            detect_ms: ms(r.timings.detect),
            describe_ms: ms(r.timings.describe),
            downsample_ms: ms(r.timings.downsample),
            register_ms: ms(r.timings.register),
            localised: r.fit.is_some(),
            fitness: r.fit.map_or(0.0, |f| f.fitness),
            tracking: r.fit.is_some_and(|f| f.tracking),
            degenerate: match r.degenerate {
                None => KEYLO_DEGENERATE_NONE,
                Some(Degenerate::TooFewPoints { .. }) => KEYLO_DEGENERATE_TOO_FEW_POINTS,
                Some(Degenerate::NoInformation { .. }) => KEYLO_DEGENERATE_NO_INFORMATION,
            },
            degenerate_minimum: match r.degenerate {
                Some(Degenerate::TooFewPoints { minimum, .. }) => saturate(minimum),
                _ => 0,
            },
            degenerate_directions: match r.degenerate {
                Some(Degenerate::NoInformation { directions }) => saturate(directions),
                _ => 0,
            },
        };
        // SAFETY: forwarded from the caller.
        unsafe { write_out(out, stats, "out") }
    })
}

/// Writes the last frame's pose to `out` (`out->size` set to `sizeof(KeyloPose)`). Returns 0,
/// or -1 before the first frame.
///
/// # Safety
/// `out` NULL or pointing to `out->size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_pose(p: *mut KeyloPipeline, out: *mut KeyloPose) -> i32 {
    with(p, |e| {
        let frames = e.frames();
        let r = last(e)?;
        let t = r.pose.translation.vector;
        let q = r.pose.rotation.quaternion();
        let matrix = keylo::rigid::pose_to_matrix(&r.pose);
        let pose = KeyloPose {
            size: 0,
            converged: r.converged,
            frames,
            stamp: r.stamp,
            translation: [t.x, t.y, t.z],
            rotation: [q.i, q.j, q.k, q.w],
            matrix,
        };
        // SAFETY: forwarded from the caller.
        unsafe { write_out(out, pose, "out") }
    })
}

/// Runs `f` on the last frame's degeneracy analysis: 0 when it wrote, 1
/// (`KEYLO_CAPI_NOT_ANALYSED`) when there is none, -1 on error.
fn with_degeneracy(
    p: *mut KeyloPipeline,
    f: impl FnOnce(&keylo::Degeneracy) -> Result<bool, CapiError>,
) -> i32 {
    let mut wrote = false;
    let rc = with(p, |e| {
        if let Some(d) = &last(e)?.degeneracy {
            wrote = f(d)?;
        }
        Ok(())
    });
    match rc {
        KEYLO_CAPI_OK if !wrote => KEYLO_CAPI_NOT_ANALYSED,
        rc => rc,
    }
}

/// Writes the last frame's degeneracy analysis to `out` (`out->size` set to
/// `sizeof(KeyloDegeneracy)`). Returns 0; 1 when the registrar did not analyse that frame
/// (the first frame, `degeneracy.analyse = false`, or a registrar without the analysis, such
/// as a plugin), `out` untouched; -1 before the first frame or when `out` is NULL.
///
/// # Safety
/// `out` NULL or pointing to `out->size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_degeneracy(
    p: *mut KeyloPipeline,
    out: *mut KeyloDegeneracy,
) -> i32 {
    with_degeneracy(p, |d| {
        let mut eigenvectors = [0.0; 36];
        for (i, v) in d.eigenvectors.iter().enumerate() {
            eigenvectors[6 * i..6 * i + 6].copy_from_slice(v);
        }
        let value = KeyloDegeneracy {
            size: 0,
            weak: d.weak as u32,
            eigenvalues: d.eigenvalues,
            eigenvectors,
            condition: d.condition,
            length_scale: d.length_scale,
            residuals: d.residuals as u64,
        };
        // SAFETY: forwarded from the caller.
        unsafe { write_out(out, value, "out") }?;
        Ok(true)
    })
}

/// The last frame's pose covariance `sigma² H⁻¹` (row-major 6x6 into `out`, twist
/// `[tx, ty, tz, rx, ry, rz]` in metres and radians) for residuals of standard deviation
/// `sigma` metres (e.g. the sensor's range noise). Returns 0; 1 when the frame has no
/// degeneracy analysis or a direction is unconstrained (`out` untouched); -1 on error.
///
/// # Safety
/// `out` NULL or pointing to 36 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_covariance(
    p: *mut KeyloPipeline,
    sigma: f64,
    out: *mut f64,
) -> i32 {
    with_degeneracy(p, |d| {
        if out.is_null() {
            return Err(CapiError::Argument("out is NULL".into()));
        }
        if !(sigma.is_finite() && sigma > 0.0) {
            return Err(CapiError::Argument(format!(
                "sigma = {sigma}: expected a positive number of metres"
            )));
        }
        let Some(c) = d.covariance(sigma) else {
            return Ok(false);
        };
        // SAFETY: 36 writable doubles per the contract.
        let out = unsafe { std::slice::from_raw_parts_mut(out, 36) };
        for (row, values) in out.chunks_exact_mut(6).zip(c) {
            row.copy_from_slice(&values);
        }
        Ok(true)
    })
}

/// The last frame's pose covariance under the noise model fitted for the registrar
/// (row-major 6x6 into `out`, twist `[tx, ty, tz, rx, ry, rz]`, world frame): what keylo's
/// pose graph and ROS 2 node use (docs/maps.md). Returns 0; 1 when the frame has no
/// degeneracy analysis (`out` untouched); -1 on error.
///
/// # Safety
/// `out` NULL or pointing to 36 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_fitted_covariance(
    p: *mut KeyloPipeline,
    out: *mut f64,
) -> i32 {
    let mut wrote = false;
    let rc = with(p, |e| {
        if out.is_null() {
            return Err(CapiError::Argument("out is NULL".into()));
        }
        let o = e
            .last()
            .ok_or_else(|| CapiError::Argument("no frame processed yet".into()))?;
        if let Some(c) = o.fitted_covariance {
            // SAFETY: 36 writable doubles per the contract.
            let out = unsafe { std::slice::from_raw_parts_mut(out, 36) };
            for (row, values) in out.chunks_exact_mut(6).zip(c) {
                row.copy_from_slice(&values);
            }
            wrote = true;
        }
        Ok(())
    });
    match rc {
        KEYLO_CAPI_OK if !wrote => KEYLO_CAPI_NOT_ANALYSED,
        rc => rc,
    }
}

/// Lends `xyz` to the caller: `*ptr` and `*n` (points).
///
/// # Safety
/// `ptr` and `n` NULL or writable.
unsafe fn lend(xyz: &[f64], ptr: *mut *const f64, n: *mut usize) -> Result<(), CapiError> {
    if ptr.is_null() || n.is_null() {
        return Err(CapiError::Argument("xyz or n is NULL".into()));
    }
    // SAFETY: writable per the contract.
    unsafe {
        *ptr = xyz.as_ptr();
        *n = xyz.len() / 3;
    }
    Ok(())
}

/// The last frame's registered cloud (what the downsampler gave the registrar) in the world
/// frame: `*xyz` receives `3 * *n` doubles, valid until the next call on `p`. Returns 0, or -1.
///
/// # Safety
/// `xyz` and `n` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_cloud(
    p: *mut KeyloPipeline,
    xyz: *mut *const f64,
    n: *mut usize,
) -> i32 {
    // SAFETY: forwarded from the caller.
    with(p, |e| unsafe { lend(e.world_cloud(), xyz, n) })
}

/// SLAM hook: the registrar's local map in the world frame: `*xyz` receives `3 * *n` doubles,
/// valid until the next call on `p` (0 points for a registrar that shows none). Returns 0, or
/// -1.
///
/// # Safety
/// `xyz` and `n` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_local_map(
    p: *mut KeyloPipeline,
    xyz: *mut *const f64,
    n: *mut usize,
) -> i32 {
    // SAFETY: forwarded from the caller.
    with(p, |e| unsafe { lend(e.local_map(), xyz, n) })
}
