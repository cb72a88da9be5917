//! Frames and point clouds in.

use std::sync::Arc;

use keylo::io::cloud::RawCloud;
use keylo::LidarFrame;
use nalgebra::Point3;

use super::handles::with;
use super::sized::read_in;
use super::types::{KeyloFrameIn, KeyloPipeline};
use crate::CapiError;

/// `n` values at `ptr`, copied, or `fill` repeated when `ptr` is NULL.
///
/// # Safety
/// `ptr` must be NULL or point to `n` values.
unsafe fn grid<T: Copy>(ptr: *const T, n: usize, fill: impl Fn(usize) -> T) -> Vec<T> {
    if ptr.is_null() || n == 0 {
        (0..n).map(fill).collect()
    } else {
        // SAFETY: non-NULL and `n` values per the caller.
        unsafe { std::slice::from_raw_parts(ptr, n) }.to_vec()
    }
}

/// The caller's frame as a keylo frame (copied).
///
/// # Safety
/// Every non-NULL pointer of `f` must hold the values its doc says.
unsafe fn frame_from(f: &KeyloFrameIn) -> Result<LidarFrame, CapiError> {
    let (rows, cols) = (f.rows as usize, f.cols as usize);
    let n = rows
        .checked_mul(cols)
        .filter(|n| n.checked_mul(3).is_some())
        .ok_or_else(|| CapiError::Argument(format!("frame: {rows} x {cols} overflows")))?;
    if n == 0 || f.xyz.is_null() {
        return Err(CapiError::Argument(format!(
            "frame: {rows} x {cols} pixels, xyz {}: expected a non-empty grid and xyz",
            if f.xyz.is_null() { "NULL" } else { "given" }
        )));
    }
    // SAFETY: non-NULL, and the caller guarantees `3 * rows * cols` floats.
    let xyz = unsafe { grid(f.xyz, 3 * n, |_| 0.0) };
    let points: Vec<Point3<f32>> = xyz
        .chunks_exact(3)
        .map(|p| Point3::new(p[0], p[1], p[2]))
        .collect();
    // SAFETY: the caller guarantees the buffer holds the documented values.
    let range = unsafe { grid(f.range, n, |i| points[i].coords.norm()) };
    // SAFETY: the caller guarantees the buffer holds the documented values.
    let valid_raw = unsafe { grid(f.valid, n, |i| u8::from(range[i] > 0.0)) };
    Ok(LidarFrame {
        index: 0,
        timestamp: f.timestamp,
        rows,
        cols,
        // SAFETY: the caller guarantees the buffer holds the documented values.
        column_times: unsafe { grid(f.column_times, cols, |_| f.timestamp) },
        pixel_times: None,
        // SAFETY: the caller guarantees the buffer holds the documented values.
        signal: unsafe { grid(f.signal, n, |_| 0.0) },
        // SAFETY: the caller guarantees the buffer holds the documented values.
        reflectivity: unsafe { grid(f.reflectivity, n, |_| 0.0) },
        // SAFETY: the caller guarantees the buffer holds the documented values.
        near_ir: unsafe { grid(f.near_ir, n, |_| 0.0) },
        valid: valid_raw.iter().map(|&v| v != 0).collect(),
        range,
        points,
        beams: Arc::new(keylo::BeamGeometry::unknown("", cols)),
        scan: None,
    })
}

/// Processes an organised frame (`frame->size` set to `sizeof(KeyloFrameIn)`). Returns 0, or
/// -1 (see `keylo_pipeline_error`).
///
/// # Safety
/// `frame` NULL or valid, its buffers holding what its doc says.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_push_frame(
    p: *mut KeyloPipeline,
    frame: *const KeyloFrameIn,
) -> i32 {
    with(p, |e| {
        // SAFETY: NULL or `frame->size` readable bytes per the contract.
        let frame = unsafe { read_in(frame, "frame") }?;
        // SAFETY: the frame's buffers hold what its doc says, per the contract.
        let frame = unsafe { frame_from(&frame) }?;
        e.push_frame(frame)
    })
}

/// Processes an unorganised cloud of `n` points (`xyz`: `3 * n` floats, sensor frame). Every
/// finite point is kept (a raw-cloud pipeline registers all of them); the `[source.projection]`
/// grid indexes them for the image stages, when the pipeline has any. `times` (per-point
/// seconds relative to `timestamp`, for deskew) and `intensity` may be NULL. Returns 0, or -1.
///
/// # Safety
/// The buffers hold `3 * n`, `n` and `n` values (or are NULL).
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_push_points(
    p: *mut KeyloPipeline,
    timestamp: f64,
    xyz: *const f32,
    times: *const f64,
    intensity: *const f32,
    n: usize,
) -> i32 {
    with(p, |e| {
        if xyz.is_null() || n == 0 {
            return Err(CapiError::Argument("points: xyz is NULL or n is 0".into()));
        }
        let len = n
            .checked_mul(3)
            .ok_or_else(|| CapiError::Argument(format!("points: n = {n} overflows")))?;
        // SAFETY: `3 * n` floats per the contract.
        let flat = unsafe { std::slice::from_raw_parts(xyz, len) };
        let cloud = RawCloud {
            timestamp,
            points: flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            // SAFETY: NULL or `n` values per the contract.
            intensity: (!intensity.is_null()).then(|| unsafe { grid(intensity, n, |_| 0.0) }),
            reflectivity: None,
            near_ir: None,
            range: None,
            ring: None,
            // SAFETY: NULL or `n` values per the contract.
            time: (!times.is_null()).then(|| unsafe { grid(times, n, |_| 0.0) }),
            grid: None,
        };
        e.push_points(&cloud)
    })
}
