//! Helpers of the C API tests: a synthetic room pushed as point clouds, the error text.

#![allow(dead_code)] // each test binary uses its own part

use std::ffi::CStr;

use keylo_capi::ffi::*;

/// A room of three walls and a floor, seen from `x` along the x axis (sensor frame), as
/// float xyz.
pub fn room(x: f32) -> Vec<f32> {
    let mut v = Vec::new();
    for i in 0..60 {
        for j in 0..20 {
            let (a, b) = (i as f32 * 0.25 - 7.0, j as f32 * 0.2);
            v.extend([a - x, 4.0, b]); // left wall
            v.extend([a - x, -4.0, b]); // right wall
            v.extend([8.0 - x, a * 0.5, b]); // end wall
            v.extend([a - x, b * 2.0 - 3.0, -1.5]); // floor
        }
    }
    v
}

pub fn error(p: *const KeyloPipeline) -> String {
    // SAFETY: a pipeline from keylo_pipeline_new; the message is NUL-terminated.
    unsafe { CStr::from_ptr(keylo_pipeline_error(p)) }
        .to_string_lossy()
        .into_owned()
}

pub fn push(p: *mut KeyloPipeline, k: usize) -> i32 {
    let xyz = room(0.1 * k as f32);
    // SAFETY: `xyz` holds 3 * n floats; times and intensity may be NULL.
    unsafe {
        keylo_pipeline_push_points(
            p,
            0.1 * k as f64,
            xyz.as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            xyz.len() / 3,
        )
    }
}

/// A pipeline from TOML text (panics with the message when it fails).
pub fn pipeline(toml: &CStr) -> *mut KeyloPipeline {
    let mut err = [0 as std::ffi::c_char; 512];
    // SAFETY: valid strings and a writable buffer of the given length.
    let p = unsafe { keylo_pipeline_new(toml.as_ptr(), std::ptr::null(), err.as_mut_ptr(), 512) };
    // SAFETY: NUL-terminated by keylo_pipeline_new on failure.
    let text = unsafe { CStr::from_ptr(err.as_ptr()) }.to_string_lossy();
    assert!(!p.is_null(), "{text}");
    p
}
