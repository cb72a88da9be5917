//! The `#[repr(C)]` types and result codes of `include/keylo.h`.

/// An organised frame: row-major `rows * cols` grids, pixel `(r, c)` at `r * cols + c`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct KeyloFrameIn {
    /// `sizeof(KeyloFrameIn)` of the caller's header (fields past it are taken as NULL/0).
    pub size: u32,
    pub rows: u32,
    pub cols: u32,
    /// Time of the first column, seconds.
    pub timestamp: f64,
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
#[derive(Debug, Clone, Copy, Default)]
pub struct KeyloPose {
    /// In: `sizeof(KeyloPose)` of the caller's header; out: the bytes written.
    pub size: u32,
    /// Whether the registrar converged on the last frame.
    pub converged: bool,
    /// Frames processed so far (since the last reset).
    pub frames: u64,
    /// Time the pose refers to, seconds.
    pub stamp: f64,
    /// Sensor position in the world (first-frame) frame, metres.
    pub translation: [f64; 3],
    /// Sensor orientation, unit quaternion x, y, z, w.
    pub rotation: [f64; 4],
    /// The same pose as a row-major 4x4 matrix.
    pub matrix: [f64; 16],
}

/// How well the last frame's geometry constrained its registration: the eigen-analysis of the
/// registrar's 6x6 point-to-plane information (twist `[tx, ty, tz, L*rx, L*ry, L*rz]`,
/// rotations scaled by `length_scale` L, per residual).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct KeyloDegeneracy {
    /// In: `sizeof(KeyloDegeneracy)` of the caller's header; out: the bytes written.
    pub size: u32,
    /// Number of weak directions: the first `weak` eigenvectors (below the registrar's
    /// `degeneracy.weak_ratio` times the largest eigenvalue).
    pub weak: u32,
    /// Eigenvalues, ascending.
    pub eigenvalues: [f64; 6],
    /// Unit eigenvectors, row-major: `eigenvectors[6 * i .. 6 * i + 6]` belongs to
    /// `eigenvalues[i]`.
    pub eigenvectors: [f64; 36],
    /// Largest over smallest eigenvalue (infinity when the smallest is not positive).
    pub condition: f64,
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
    /// Whether the registrar localises in a prior map (`[registrar] kind = "localise"`):
    /// then `fitness` and `tracking` hold the frame's fit; else they are 0 and false.
    pub localised: bool,
    /// Share of the registered points with a map point within the fitness distance.
    pub fitness: f64,
    /// The fitness reached its threshold; a frame not tracking has a pose not to be trusted.
    pub tracking: bool,
    /// Why the registration could not constrain the pose (its pose is then, at least in
    /// part, the motion model's prediction): `KEYLO_DEGENERATE_NONE`,
    /// `KEYLO_DEGENERATE_TOO_FEW_POINTS` (`registered_points` below `degenerate_minimum`) or
    /// `KEYLO_DEGENERATE_NO_INFORMATION` (`degenerate_directions` of the six without
    /// information).
    pub degenerate: u32,
    /// The registrar's minimum of registered points (with `KEYLO_DEGENERATE_TOO_FEW_POINTS`).
    pub degenerate_minimum: u32,
    /// Pose directions without information (with `KEYLO_DEGENERATE_NO_INFORMATION`).
    pub degenerate_directions: u32,
}

/// `KeyloFrameStats::degenerate`: the frame is not degenerate.
pub const KEYLO_DEGENERATE_NONE: u32 = 0;
/// `KeyloFrameStats::degenerate`: fewer registered points than the registrar's minimum.
pub const KEYLO_DEGENERATE_TOO_FEW_POINTS: u32 = 1;
/// `KeyloFrameStats::degenerate`: the degeneracy analysis found a direction without
/// information.
pub const KEYLO_DEGENERATE_NO_INFORMATION: u32 = 2;

/// A keylo pipeline (opaque). A handle, not an address: a freed or made-up handle is
/// recognised and refused (`KEYLO_CAPI_ERROR`), never dereferenced.
pub struct KeyloPipeline {
    _opaque: [u8; 0],
}

/// Success.
pub const KEYLO_CAPI_OK: i32 = 0;
/// Failure: see `keylo_pipeline_error`.
pub const KEYLO_CAPI_ERROR: i32 = -1;
/// Refused: another thread is inside a call on the same pipeline (nothing was done, and the
/// error text is not changed). A pipeline is used by one thread at a time.
pub const KEYLO_CAPI_BUSY: i32 = -2;
/// `keylo_pipeline_new_with_flags`: load the libraries the config names itself (plugins in
/// its `[plugins] dirs`, an `onnxruntime` path), whose code then runs. Without it such a
/// config is refused; plugins installed in KEYLO_PLUGIN_PATH or ~/.local/lib/keylo/plugins
/// load either way (docs/plugins.md, "Trust").
pub const KEYLO_TRUST_PLUGINS: u32 = 1;

/// `keylo_pipeline_degeneracy` / `keylo_pipeline_covariance`: the last frame has no
/// degeneracy analysis (or, for the covariance, an unconstrained direction).
pub const KEYLO_CAPI_NOT_ANALYSED: i32 = 1;
