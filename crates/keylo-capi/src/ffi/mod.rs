//! The `extern "C"` functions and `#[repr(C)]` types of `include/keylo.h` (generated from
//! these files by cbindgen; a test fails when the committed header differs).
//!
//! Every function catches panics; a failing call returns non-zero (or NULL) and
//! `keylo_pipeline_error` says why. Pointers returned stay valid until the next call on the
//! same pipeline. A pipeline is used by one thread at a time. Handles are looked up, never
//! dereferenced ([`handles`]).

mod handles;
mod hooks;
mod input;
mod map;
mod output;
mod pipeline;
mod sized;
mod types;

pub use hooks::{keylo_pipeline_reset, keylo_pipeline_set_motion_prior, keylo_pipeline_set_pose};
pub use input::{keylo_pipeline_push_frame, keylo_pipeline_push_points};
pub use map::{keylo_pipeline_finish_map, keylo_pipeline_save_map};
pub use output::{
    keylo_pipeline_cloud, keylo_pipeline_covariance, keylo_pipeline_degeneracy,
    keylo_pipeline_local_map, keylo_pipeline_pose, keylo_pipeline_stats,
};
pub use pipeline::{
    keylo_pipeline_error, keylo_pipeline_free, keylo_pipeline_new, keylo_pipeline_new_with_flags,
    keylo_version,
};
pub use types::*;

/// The source files cbindgen reads for `include/keylo.h`, in header order.
pub const HEADER_SOURCES: [&str; 7] = [
    "src/ffi/types.rs",
    "src/ffi/pipeline.rs",
    "src/ffi/input.rs",
    "src/ffi/hooks.rs",
    "src/ffi/map.rs",
    "src/ffi/output.rs",
    "src/ffi/sized.rs",
];
