//! The `extern "C"` functions and `#[repr(C)]` types of `include/keylo.h` (generated from this
//! file by cbindgen; a test fails when the committed header differs).
//!
//! Every function catches panics; a failing call returns non-zero (or NULL) and
//! `keylo_pipeline_error` says why. Pointers returned stay valid until the next call on the
//! same pipeline. A pipeline is used by one thread at a time.

use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use keylo::io::cloud::RawCloud;
use keylo::LidarFrame;
use nalgebra::Point3;

use crate::{CapiError, Embedded};

/// An organised frame: row-major `rows * cols` grids, pixel `(r, c)` at `r * cols + c`.
#[repr(C)]
pub struct KeyloFrameIn {
    /// Time of the first column, seconds.
    pub timestamp: f64,
    pub rows: u32,
    pub cols: u32,
    /// Firing time of every column, absolute seconds (`cols` values), or NULL: all
    /// `timestamp` (no deskew).
    pub column_times: *const f64,
    /// xyz per pixel in the sensor frame, metres (`3 * rows * cols` values).
    pub xyz: *const f32,
    /// Range per pixel, metres, or NULL: the norm of the point.
    pub range: *const f32,
    /// Signal (intensity) per pixel, or NULL: zeros.
    pub signal: *const f32,
    /// Reflectivity per pixel, or NULL: zeros.
    pub reflectivity: *const f32,
    /// Near-IR per pixel, or NULL: zeros.
    pub near_ir: *const f32,
    /// 1 where the pixel holds a return, or NULL: where the range is positive.
    pub valid: *const u8,
}

/// The pose of the last frame.
#[repr(C)]
pub struct KeyloPose {
    /// Time the pose refers to, seconds.
    pub stamp: f64,
    /// Sensor position in the world (first-frame) frame, metres.
    pub translation: [f64; 3],
    /// Sensor orientation, unit quaternion x, y, z, w.
    pub rotation: [f64; 4],
    /// The same pose as a row-major 4x4 matrix.
    pub matrix: [f64; 16],
    /// Frames processed so far.
    pub frames: u64,
    /// Whether the registrar converged on the last frame.
    pub converged: bool,
}

/// How well the last frame's geometry constrained its registration: the eigen-analysis of the
/// registrar's 6x6 point-to-plane information (twist `[tx, ty, tz, L*rx, L*ry, L*rz]`,
/// rotations scaled by `length_scale` L, per residual).
#[repr(C)]
pub struct KeyloDegeneracy {
    /// Eigenvalues, ascending.
    pub eigenvalues: [f64; 6],
    /// Unit eigenvectors, row-major: `eigenvectors[6 * i .. 6 * i + 6]` belongs to
    /// `eigenvalues[i]`.
    pub eigenvectors: [f64; 36],
    /// Largest over smallest eigenvalue (infinity when the smallest is not positive).
    pub condition: f64,
    /// Number of weak directions: the first `weak` eigenvectors (below the registrar's
    /// `degeneracy.weak_ratio` times the largest eigenvalue).
    pub weak: u32,
    /// The rotation scale L, metres.
    pub length_scale: f64,
    /// Residuals the matrix sums over.
    pub residuals: u64,
}

/// Statistics of the last frame. It may grow: set `size` to `sizeof(KeyloFrameStats)` before
/// `keylo_pipeline_stats`, which writes only the fields that fit.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct KeyloFrameStats {
    /// In: the struct's size as the caller's header declares it; out: the bytes written.
    pub size: u32,
    /// Index of the frame (0 for the first pushed).
    pub frame: u64,
    /// Keypoints found over all images.
    pub keypoints: u64,
    /// Points the downsampler handed to the registrar.
    pub cloud_points: u64,
    /// Points the registrar aligned after its own downsampling (0: the pose was predicted).
    pub registered_points: u64,
    /// Points in the local map after the frame.
    pub map_points: u64,
    /// Solver iterations.
    pub iterations: u64,
    /// Whether the solver converged.
    pub converged: bool,
    /// Milliseconds in each stage: images, detection, description, downsampling,
    /// registration.
    pub image_ms: f64,
    pub detect_ms: f64,
    pub describe_ms: f64,
    pub downsample_ms: f64,
    pub register_ms: f64,
}

/// A keylo pipeline (opaque).
pub struct KeyloPipeline {
    inner: Option<Embedded>,
    error: CString,
    /// Set while a call runs on this pipeline: a call from a second thread meanwhile is
    /// refused with `KEYLO_CAPI_BUSY` instead of racing.
    busy: AtomicBool,
}

/// Success.
pub const KEYLO_CAPI_OK: i32 = 0;
/// Failure: see `keylo_pipeline_error`.
pub const KEYLO_CAPI_ERROR: i32 = -1;
/// Refused: another thread is inside a call on the same pipeline (nothing was done, and the
/// error text is not changed). A pipeline is used by one thread at a time.
pub const KEYLO_CAPI_BUSY: i32 = -2;
/// `keylo_pipeline_degeneracy`: the last frame has no degeneracy analysis.
pub const KEYLO_CAPI_NOT_ANALYSED: i32 = 1;

fn panic_text(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_default()
}

fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

/// Runs `f` on the pipeline, recording its error.
fn with(p: *mut KeyloPipeline, f: impl FnOnce(&mut Embedded) -> Result<(), CapiError>) -> i32 {
    if p.is_null() {
        return KEYLO_CAPI_ERROR;
    }
    // SAFETY: a non-NULL pipeline comes from `keylo_pipeline_new` (the API's contract); only
    // the atomic flag is touched before this thread owns the pipeline.
    let busy = unsafe { &(*p).busy };
    if busy
        .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        return KEYLO_CAPI_BUSY;
    }
    let code = with_owned(p, f);
    busy.store(false, Ordering::Release);
    code
}

/// [`with`] once this thread holds the pipeline's `busy` flag.
fn with_owned(
    p: *mut KeyloPipeline,
    f: impl FnOnce(&mut Embedded) -> Result<(), CapiError>,
) -> i32 {
    // SAFETY: non-NULL (checked by `with`), and no other thread is inside a call on it. Only
    // the fields this call changes are borrowed: other threads may read `busy` meanwhile.
    let (inner, error) = unsafe { (&mut (*p).inner, &mut (*p).error) };
    let outcome = match inner.as_mut() {
        None => Err(CapiError::Argument(
            "the pipeline failed earlier; free it".into(),
        )),
        Some(e) => match catch_unwind(AssertUnwindSafe(|| f(e))) {
            Ok(r) => r,
            Err(panic) => {
                *inner = None;
                Err(CapiError::Panic(panic_text(panic)))
            }
        },
    };
    match outcome {
        Ok(()) => {
            *error = CString::default();
            KEYLO_CAPI_OK
        }
        Err(e) => {
            *error = to_cstring(&e.to_string());
            KEYLO_CAPI_ERROR
        }
    }
}

/// The keylo version, a static NUL-terminated string.
#[no_mangle]
pub extern "C" fn keylo_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// A pipeline from a TOML config (the format of `keylo run` configs; `[source]` is not used
/// except `[source.projection]` for `keylo_pipeline_push_points`). Relative paths resolve
/// against `base_dir` (NULL: the current folder). On failure: NULL, and the message is written
/// to `error` (`error_len` bytes, NUL-terminated) when it is not NULL.
///
/// # Safety
/// `toml` and `base_dir` must be NULL or NUL-terminated; `error` must have `error_len`
/// writable bytes.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_new(
    toml: *const c_char,
    base_dir: *const c_char,
    error: *mut c_char,
    error_len: usize,
) -> *mut KeyloPipeline {
    let made = catch_unwind(AssertUnwindSafe(|| {
        if toml.is_null() {
            return Err(CapiError::Argument("toml is NULL".into()));
        }
        // SAFETY: NUL-terminated per the contract.
        let text = unsafe { CStr::from_ptr(toml) }
            .to_str()
            .map_err(|_| CapiError::Argument("toml is not UTF-8".into()))?;
        let base = if base_dir.is_null() {
            std::path::PathBuf::from(".")
        } else {
            // SAFETY: NUL-terminated per the contract.
            let s = unsafe { CStr::from_ptr(base_dir) }.to_string_lossy();
            std::path::PathBuf::from(s.into_owned())
        };
        Embedded::new(text, &base)
    }))
    .unwrap_or_else(|e| Err(CapiError::Panic(panic_text(e))));
    match made {
        Ok(inner) => Box::into_raw(Box::new(KeyloPipeline {
            inner: Some(inner),
            error: CString::default(),
            busy: AtomicBool::new(false),
        })),
        Err(e) => {
            if !error.is_null() && error_len > 0 {
                let msg = e.to_string();
                let n = msg.len().min(error_len - 1);
                // SAFETY: `error` has `error_len` writable bytes per the contract.
                unsafe {
                    std::ptr::copy_nonoverlapping(msg.as_ptr(), error.cast::<u8>(), n);
                    *error.add(n) = 0;
                }
            }
            std::ptr::null_mut()
        }
    }
}

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

/// Processes an organised frame. Returns 0, or -1 (see `keylo_pipeline_error`).
///
/// # Safety
/// `p` from `keylo_pipeline_new`; `frame` valid, its buffers holding what its doc says.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_push_frame(
    p: *mut KeyloPipeline,
    frame: *const KeyloFrameIn,
) -> i32 {
    with(p, |e| {
        if frame.is_null() {
            return Err(CapiError::Argument("frame is NULL".into()));
        }
        // SAFETY: valid frame per the contract.
        let frame = unsafe { frame_from(&*frame) }?;
        e.push_frame(frame)
    })
}

/// Processes an unorganised cloud of `n` points (`xyz`: `3 * n` floats, sensor frame). Every
/// finite point is kept (a raw-cloud pipeline registers all of them); the `[source.projection]`
/// grid indexes them for the image stages, when the pipeline has any. `times` (per-point
/// seconds relative to `timestamp`, for deskew) and `intensity` may be NULL. Returns 0, or -1.
///
/// # Safety
/// `p` from `keylo_pipeline_new`; the buffers hold `3 * n`, `n` and `n` values.
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

/// A row-major 4x4 rigid transform as an isometry; an error naming `what` when it is not one
/// (non-finite, a last row other than 0 0 0 1, or a 3x3 part that is not a rotation within
/// 1e-6).
fn rigid(m: &[f64; 16], what: &str) -> Result<keylo::Pose, CapiError> {
    let bad = |why: &str| CapiError::Argument(format!("{what}: not a rigid transform ({why})"));
    if !m.iter().all(|v| v.is_finite()) {
        return Err(bad("a non-finite entry"));
    }
    if m[12..] != [0.0, 0.0, 0.0, 1.0] {
        return Err(bad("the last row is not 0 0 0 1"));
    }
    let r = nalgebra::Matrix3::new(m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]);
    let off = (r.transpose() * r - nalgebra::Matrix3::identity())
        .abs()
        .max();
    if off > 1e-6 || r.determinant() < 0.0 {
        return Err(bad("the 3x3 part is not a rotation"));
    }
    let rotation = nalgebra::UnitQuaternion::from_matrix(&r);
    let translation = nalgebra::Translation3::new(m[3], m[7], m[11]);
    Ok(keylo::Pose::from_parts(translation, rotation))
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
/// `p` from `keylo_pipeline_new`; `matrix` points to 16 doubles.
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
/// `p` from `keylo_pipeline_new`; `matrix` points to 16 doubles.
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
/// `p` from `keylo_pipeline_new`.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_reset(p: *mut KeyloPipeline) -> i32 {
    with(p, |e| e.reset())
}

/// Writes the last frame's statistics to `out` (its `size` set by the caller; at least the
/// bytes up to and including `frame`). Returns 0, or -1 before the first frame or when `size`
/// is too small.
///
/// # Safety
/// `p` from `keylo_pipeline_new`; `out` points to `out->size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_stats(
    p: *mut KeyloPipeline,
    out: *mut KeyloFrameStats,
) -> i32 {
    with(p, |e| {
        if out.is_null() {
            return Err(CapiError::Argument("out is NULL".into()));
        }
        // SAFETY: `size`, the first field, is readable per the contract.
        let size = unsafe { std::ptr::addr_of!((*out).size).read_unaligned() } as usize;
        let needed = std::mem::offset_of!(KeyloFrameStats, frame) + std::mem::size_of::<u64>();
        if size < needed {
            return Err(CapiError::Argument(format!(
                "out->size = {size}: set it to sizeof(KeyloFrameStats) (at least {needed})"
            )));
        }
        let r = e
            .last()
            .ok_or_else(|| CapiError::Argument("no frame processed yet".into()))?;
        let ms = |s: f64| 1e3 * s;
        let full = std::mem::size_of::<KeyloFrameStats>();
        let written = size.min(full);
        let stats = KeyloFrameStats {
            size: written as u32,
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
        };
        // SAFETY: `written` ≤ both the caller's buffer and the struct; a prefix of a repr(C)
        // struct is a valid prefix of any later version of it.
        unsafe {
            std::ptr::copy_nonoverlapping(
                (&stats as *const KeyloFrameStats).cast::<u8>(),
                out.cast::<u8>(),
                written,
            );
        }
        Ok(())
    })
}

/// Writes the last frame's pose to `out`. Returns 0, or -1 before the first frame.
///
/// # Safety
/// `p` from `keylo_pipeline_new`; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_pose(p: *mut KeyloPipeline, out: *mut KeyloPose) -> i32 {
    with(p, |e| {
        let r = e
            .last()
            .ok_or_else(|| CapiError::Argument("no frame processed yet".into()))?;
        if out.is_null() {
            return Err(CapiError::Argument("out is NULL".into()));
        }
        let t = r.pose.translation.vector;
        let q = r.pose.rotation.quaternion();
        let m = r.pose.to_homogeneous();
        let mut matrix = [0.0; 16];
        for (i, v) in matrix.iter_mut().enumerate() {
            *v = m[(i / 4, i % 4)];
        }
        // SAFETY: writable per the contract.
        unsafe {
            *out = KeyloPose {
                stamp: r.stamp,
                translation: [t.x, t.y, t.z],
                rotation: [q.i, q.j, q.k, q.w],
                matrix,
                frames: r.index + 1,
                converged: r.converged,
            };
        }
        Ok(())
    })
}

/// Writes the last frame's degeneracy analysis to `out`. Returns 0; 1 when the registrar did
/// not analyse that frame (the first frame, `degeneracy.analyse = false`, or a registrar
/// without the analysis, such as a plugin), `out` untouched; -1 before the first frame or
/// when `out` is NULL.
///
/// # Safety
/// `p` from `keylo_pipeline_new`; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_degeneracy(
    p: *mut KeyloPipeline,
    out: *mut KeyloDegeneracy,
) -> i32 {
    let mut analysed = false;
    let rc = with(p, |e| {
        let r = e
            .last()
            .ok_or_else(|| CapiError::Argument("no frame processed yet".into()))?;
        if out.is_null() {
            return Err(CapiError::Argument("out is NULL".into()));
        }
        let Some(d) = &r.degeneracy else {
            return Ok(());
        };
        let mut eigenvectors = [0.0; 36];
        for (i, v) in d.eigenvectors.iter().enumerate() {
            eigenvectors[6 * i..6 * i + 6].copy_from_slice(v);
        }
        // SAFETY: writable per the contract.
        unsafe {
            *out = KeyloDegeneracy {
                eigenvalues: d.eigenvalues,
                eigenvectors,
                condition: d.condition,
                weak: d.weak as u32,
                length_scale: d.length_scale,
                residuals: d.residuals as u64,
            };
        }
        analysed = true;
        Ok(())
    });
    match rc {
        KEYLO_CAPI_OK if !analysed => KEYLO_CAPI_NOT_ANALYSED,
        rc => rc,
    }
}

/// The last frame's registered cloud (what the downsampler gave the registrar) in the world
/// frame: `*xyz` receives `3 * *n` doubles, valid until the next call on `p`. Returns 0, or -1.
///
/// # Safety
/// `p` from `keylo_pipeline_new`; `xyz` and `n` writable.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_cloud(
    p: *mut KeyloPipeline,
    xyz: *mut *const f64,
    n: *mut usize,
) -> i32 {
    with(p, |e| {
        if xyz.is_null() || n.is_null() {
            return Err(CapiError::Argument("xyz or n is NULL".into()));
        }
        let c = e.world_cloud();
        // SAFETY: writable per the contract.
        unsafe {
            *xyz = c.as_ptr();
            *n = c.len() / 3;
        }
        Ok(())
    })
}

/// Why the last call on `p` failed ("" after a success). Valid until the next call on `p`.
///
/// # Safety
/// `p` NULL or from `keylo_pipeline_new`.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_error(p: *const KeyloPipeline) -> *const c_char {
    if p.is_null() {
        return c"pipeline is NULL".as_ptr();
    }
    // SAFETY: from `keylo_pipeline_new` per the contract.
    let busy = unsafe { &(*p).busy };
    if busy.load(Ordering::Acquire) {
        return c"the pipeline is busy in another thread".as_ptr();
    }
    // SAFETY: as above; no call is running, so nothing writes the text.
    unsafe { &(*p).error }.as_ptr()
}

/// Frees a pipeline (NULL is allowed).
///
/// # Safety
/// `p` NULL or from `keylo_pipeline_new`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_free(p: *mut KeyloPipeline) {
    if !p.is_null() {
        // A call still running in another thread finishes first.
        // SAFETY: from `keylo_pipeline_new`, not freed yet per the contract.
        let busy = unsafe { &(*p).busy };
        while busy
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
        {
            std::thread::yield_now();
        }
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: from `keylo_pipeline_new`, freed once per the contract.
            drop(unsafe { Box::from_raw(p) });
        }));
    }
}
