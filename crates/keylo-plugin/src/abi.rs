//! The C ABI between keylo and its plugins, version [`KEYLO_PLUGIN_ABI_VERSION`].
//!
//! `include/keylo_plugin.h` is generated from this file by cbindgen (a test fails when the
//! committed header differs). Conventions:
//!
//! - A plugin library exports one symbol, `keylo_plugin_entry`, returning a pointer to a
//!   [`KeyloPluginInfo`] that lives as long as the library. Its first field is the ABI version.
//! - Every call gets a [`KeyloError`] to fill and returns [`KEYLO_OK`] or an error code.
//! - Input buffers belong to keylo and are valid during the call only. Output buffers
//!   (keypoints, descriptors, clouds) belong to the plugin instance and must stay valid until
//!   the next call on that instance or its destruction.
//! - One instance is used by one thread at a time; different instances may run in parallel.
//!
//! Versions. A newer version adds structs, and appends fields only to the end of a struct
//! keylo allocates and lends by pointer (never to an array element or a struct the plugin
//! fills), so a plugin built against an older header reads a prefix of what it is given and
//! keeps loading; [`KeyloPluginInfo::abi_version`] says which fields it knows of.
//!
//! - 1: the first version.
//! - 2: [`KeyloFrame::scan`], every point of an unorganised scan ([`KeyloScanPoints`]).
//! - 3: the SLAM hooks of a registrar, appended to [`KeyloPluginKind`]. The plugin fills the
//!   kinds array, so here keylo reads a version-1/2 plugin's array with the old, shorter
//!   element and takes the hooks as absent.

use std::ffi::{c_char, c_void};

/// The ABI version this header describes. keylo loads plugins of this version and of every
/// earlier one (1, 2 and 3), and refuses any other.
pub const KEYLO_PLUGIN_ABI_VERSION: u32 = 3;

/// Bytes of [`KeyloError::message`], terminating NUL included.
pub const KEYLO_ERROR_MESSAGE_LEN: usize = 512;

/// Success.
pub const KEYLO_OK: i32 = 0;
/// The configuration (TOML) was rejected.
pub const KEYLO_ERR_CONFIG: i32 = 1;
/// The input (image, frame, cloud) cannot be processed.
pub const KEYLO_ERR_INPUT: i32 = 2;
/// Any other failure inside the plugin.
pub const KEYLO_ERR_INTERNAL: i32 = 3;
/// The plugin panicked (Rust SDK) or threw (C++); the message says where.
pub const KEYLO_ERR_PANIC: i32 = 4;

/// `[detector]` stage: image → keypoints.
pub const KEYLO_STAGE_DETECTOR: u32 = 1;
/// `[descriptor]` stage: image + keypoints → descriptors.
pub const KEYLO_STAGE_DESCRIPTOR: u32 = 2;
/// `[downsampler]` stage: frame + features → cloud.
pub const KEYLO_STAGE_DOWNSAMPLER: u32 = 3;
/// `[registrar]` stage: cloud → pose.
pub const KEYLO_STAGE_REGISTRAR: u32 = 4;

/// [`KeyloImage::pixel_type`]: 8-bit unsigned samples.
pub const KEYLO_PIXEL_U8: u32 = 0;

/// [`KeyloScanPoints::pixel`]: the point lies outside the frame grid;
/// [`KeyloScanPoints::pixel_to_point`]: the pixel holds no point. (`UINT32_MAX`)
pub const KEYLO_SCAN_NONE: u32 = 0xFFFF_FFFF;

/// [`KeyloDescriptors::element_type`]: binary descriptors, one byte per element (Hamming).
pub const KEYLO_DESCRIPTOR_U8: u32 = 0;
/// [`KeyloDescriptors::element_type`]: float descriptors (L2).
pub const KEYLO_DESCRIPTOR_F32: u32 = 1;

/// An error: a code and a NUL-terminated message. keylo zeroes it before every call.
#[repr(C)]
pub struct KeyloError {
    /// One of the `KEYLO_ERR_*` codes.
    pub code: i32,
    /// What went wrong, NUL-terminated UTF-8.
    pub message: [c_char; KEYLO_ERROR_MESSAGE_LEN],
}

/// An image: `height` rows of `width` pixels of `channels` interleaved samples; row `y`
/// starts at byte `y * stride`.
#[repr(C)]
pub struct KeyloImage {
    pub width: u32,
    pub height: u32,
    /// Bytes from one row to the next.
    pub stride: u32,
    /// Interleaved planes (1 for most detectors).
    pub channels: u32,
    /// [`KEYLO_PIXEL_U8`].
    pub pixel_type: u32,
    /// `height * stride` bytes.
    pub data: *const u8,
    /// Image pixel to frame grid: `col = x * scale_x`, `row = y * scale_y`.
    pub scale_x: f64,
    pub scale_y: f64,
    /// The frame channels the image was made from, joined by `+` (`signal`, `signal+range`).
    pub name: *const c_char,
}

/// A keypoint in image pixels, the fields of OpenCV's `cv::KeyPoint`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KeyloKeypoint {
    pub x: f32,
    pub y: f32,
    /// Diameter of the meaningful neighbourhood, pixels.
    pub size: f32,
    /// Orientation in degrees, -1 when not applicable.
    pub angle: f32,
    /// Detector response (strength).
    pub response: f32,
    /// Pyramid octave.
    pub octave: i32,
    /// Detector-specific id.
    pub class_id: i32,
}

/// A list of keypoints.
#[repr(C)]
pub struct KeyloKeypoints {
    pub data: *const KeyloKeypoint,
    pub len: usize,
}

/// A descriptor matrix: `rows` descriptors of `dim` elements of `element_type`.
#[repr(C)]
pub struct KeyloDescriptors {
    /// [`KEYLO_DESCRIPTOR_U8`] or [`KEYLO_DESCRIPTOR_F32`].
    pub element_type: u32,
    pub rows: usize,
    pub dim: usize,
    /// `rows * dim` elements, row-major; NULL when `rows` is 0.
    pub data: *const c_void,
}

/// A frame: every grid is row-major `rows * cols`, pixel `(r, c)` at `r * cols + c`. An
/// organised sensor delivers one point per pixel; an unorganised scan also carries all its
/// points in `scan` (ABI version 2), the grids showing the nearest point of each pixel.
#[repr(C)]
pub struct KeyloFrame {
    /// Sequence number in the source.
    pub index: u64,
    /// Time of the first column, seconds.
    pub timestamp: f64,
    pub rows: u32,
    pub cols: u32,
    /// Firing time of every column, seconds (`cols` values).
    pub column_times: *const f64,
    /// Firing time of every pixel, seconds, or NULL when pixels have their column's time.
    pub pixel_times: *const f64,
    /// Range, metres.
    pub range: *const f32,
    pub signal: *const f32,
    pub reflectivity: *const f32,
    pub near_ir: *const f32,
    /// xyz per pixel in the sensor frame, metres (`3 * rows * cols` values).
    pub points: *const f32,
    /// Whether each pixel holds a return.
    pub valid: *const bool,
    /// ABI version 2: every point of an unorganised scan (KITTI `.bin`, PLY, PCD, an
    /// unorganised `PointCloud2`), or NULL for an organised frame. A plugin of version 1 does
    /// not see this field; keylo always allocates it.
    pub scan: *const KeyloScanPoints,
}

/// Every finite point of an unorganised scan in file order, with the frame pixel each falls
/// into (ABI version 2). A pixel may hold several points, or none; the frame's grids show the
/// nearest point of each pixel (`pixel_to_point`). Per-point arrays hold `len` values.
#[repr(C)]
pub struct KeyloScanPoints {
    /// Number of points.
    pub len: usize,
    /// xyz per point in the sensor frame, metres (`3 * len` values, all finite).
    pub xyz: *const f64,
    /// Firing time of every point relative to the frame's `timestamp`, seconds, or NULL when
    /// the source knows no per-point time.
    pub times: *const f64,
    /// Intensity of every point, or NULL when the file has none.
    pub intensity: *const f32,
    /// Beam (ring) of every point, or NULL when the file has none.
    pub ring: *const u16,
    /// Index of every point in its file or message (non-finite points are skipped, so the
    /// indices can jump).
    pub source_index: *const u32,
    /// Row-major frame pixel of every point, or [`KEYLO_SCAN_NONE`] when the point lies
    /// outside the grid (beyond the vertical field of view, or at the origin).
    pub pixel: *const u32,
    /// Per frame pixel (`rows * cols` values), the point the grids show: the nearest point of
    /// the pixel (the first in file order among equally near ones), or [`KEYLO_SCAN_NONE`].
    pub pixel_to_point: *const u32,
}

/// The keypoints (and descriptors, `rows` 0 when none) found in one image of a frame.
#[repr(C)]
pub struct KeyloImageFeatures {
    pub image: KeyloImage,
    pub keypoints: KeyloKeypoints,
    pub descriptors: KeyloDescriptors,
}

/// Everything the feature stages found in one frame.
#[repr(C)]
pub struct KeyloFeatures {
    pub images: *const KeyloImageFeatures,
    pub len: usize,
}

/// An unorganised cloud in the sensor frame.
#[repr(C)]
pub struct KeyloCloud {
    /// Scan start, seconds.
    pub timestamp: f64,
    pub len: usize,
    /// xyz per point, metres (`3 * len` values).
    pub xyz: *const f64,
    /// Per-point time relative to `timestamp`, seconds, or NULL.
    pub times: *const f64,
    /// Per-point intensity, or NULL.
    pub intensities: *const f32,
}

/// The outcome of registering one cloud.
#[repr(C)]
pub struct KeyloRegistration {
    /// Time the pose refers to, seconds.
    pub stamp: f64,
    /// Sensor position in the world (first-frame) frame, metres.
    pub translation: [f64; 3],
    /// Sensor orientation as a unit quaternion x, y, z, w.
    pub rotation: [f64; 4],
    /// Points used after the registrar's own preprocessing.
    pub source_points: usize,
    pub iterations: usize,
    pub converged: bool,
    /// Points in the local map after this cloud.
    pub map_size: usize,
}

/// Creates an instance (unconfigured); NULL with `err` filled on failure.
pub type KeyloCreateFn = Option<unsafe extern "C" fn(err: *mut KeyloError) -> *mut c_void>;
/// Configures an instance from the stage's TOML table (without `kind`), serialised to text.
/// keylo calls it once, right after `create`, before any run.
pub type KeyloConfigureFn = Option<
    unsafe extern "C" fn(state: *mut c_void, toml: *const c_char, err: *mut KeyloError) -> i32,
>;
/// Frees an instance and every buffer it handed out.
pub type KeyloDestroyFn = Option<unsafe extern "C" fn(state: *mut c_void)>;
/// Detector run: fills `out` with the keypoints of `image`.
pub type KeyloDetectFn = Option<
    unsafe extern "C" fn(
        state: *mut c_void,
        image: *const KeyloImage,
        out: *mut KeyloKeypoints,
        err: *mut KeyloError,
    ) -> i32,
>;
/// Descriptor run: describes `keypoints`; `out_keypoints` receives the keypoints kept (row `i`
/// of `out` describes `out_keypoints[i]`).
pub type KeyloDescribeFn = Option<
    unsafe extern "C" fn(
        state: *mut c_void,
        image: *const KeyloImage,
        keypoints: *const KeyloKeypoints,
        out_keypoints: *mut KeyloKeypoints,
        out: *mut KeyloDescriptors,
        err: *mut KeyloError,
    ) -> i32,
>;
/// Downsampler run: the cloud to register, chosen from `frame` and its `features`.
pub type KeyloDownsampleFn = Option<
    unsafe extern "C" fn(
        state: *mut c_void,
        frame: *const KeyloFrame,
        features: *const KeyloFeatures,
        out: *mut KeyloCloud,
        err: *mut KeyloError,
    ) -> i32,
>;
/// Registrar run: registers the next cloud and writes its pose to `out`.
pub type KeyloRegisterFn = Option<
    unsafe extern "C" fn(
        state: *mut c_void,
        cloud: *const KeyloCloud,
        out: *mut KeyloRegistration,
        err: *mut KeyloError,
    ) -> i32,
>;

/// SLAM hook of a registrar (ABI 3, optional): a row-major 4x4 rigid transform (16 doubles).
/// `set_motion_prior`: the motion from the last cloud to the next (`last_pose⁻¹ · next_pose`,
/// e.g. from an IMU), replacing the registrar's own guess for the next cloud only;
/// `set_pose`: the last cloud's pose becomes `matrix`, map and motion kept.
pub type KeyloMatrixFn = Option<
    unsafe extern "C" fn(state: *mut c_void, matrix: *const f64, err: *mut KeyloError) -> i32,
>;
/// SLAM hook of a registrar (ABI 3, optional): forget map and motion; the next cloud starts a
/// new trajectory at the identity.
pub type KeyloResetFn =
    Option<unsafe extern "C" fn(state: *mut c_void, err: *mut KeyloError) -> i32>;
/// SLAM hook of a registrar (ABI 3, optional): the local map in the world frame: `*xyz`
/// receives `3 * *n` doubles owned by the instance, valid until its next call.
pub type KeyloLocalMapFn = Option<
    unsafe extern "C" fn(
        state: *mut c_void,
        xyz: *mut *const f64,
        n: *mut usize,
        err: *mut KeyloError,
    ) -> i32,
>;

/// One backend a plugin offers. `create`, `configure` and `destroy` are required, and the run
/// function of `stage` (`detect` for [`KEYLO_STAGE_DETECTOR`], …); the others are NULL.
/// A registrar may also offer the SLAM hooks (ABI 3; NULL: "does not offer", an error when
/// called).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct KeyloPluginKind {
    /// One of the `KEYLO_STAGE_*` values. A plugin offers at most one kind per stage.
    pub stage: u32,
    /// One line saying what the backend does (NUL-terminated UTF-8).
    pub summary: *const c_char,
    pub create: KeyloCreateFn,
    pub configure: KeyloConfigureFn,
    pub destroy: KeyloDestroyFn,
    pub detect: KeyloDetectFn,
    pub describe: KeyloDescribeFn,
    pub downsample: KeyloDownsampleFn,
    pub register_cloud: KeyloRegisterFn,
    /// ABI 3: [`KeyloMatrixFn`] hooks, [`KeyloResetFn`], [`KeyloLocalMapFn`].
    pub set_motion_prior: KeyloMatrixFn,
    pub set_pose: KeyloMatrixFn,
    pub reset: KeyloResetFn,
    pub local_map: KeyloLocalMapFn,
}

/// What `keylo_plugin_entry` returns. `abi_version` must stay the first field in every
/// version of the ABI: keylo reads it before anything else.
#[repr(C)]
pub struct KeyloPluginInfo {
    /// [`KEYLO_PLUGIN_ABI_VERSION`] of the header the plugin was built with.
    pub abi_version: u32,
    /// Plugin name, as in `kind = "plugin:NAME"` (NUL-terminated UTF-8).
    pub name: *const c_char,
    /// Plugin version, free text (NUL-terminated UTF-8).
    pub version: *const c_char,
    /// `kind_count` kinds.
    pub kinds: *const KeyloPluginKind,
    pub kind_count: usize,
}

/// The type of the `keylo_plugin_entry` symbol.
pub type KeyloPluginEntryFn = unsafe extern "C" fn() -> *const KeyloPluginInfo;
