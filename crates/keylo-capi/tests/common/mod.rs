//! Helpers of the C API tests: a synthetic room pushed as point clouds, the error text.

#![allow(dead_code)] // each test binary uses its own part

use std::ffi::CStr;
use std::path::{Path, PathBuf};

use keylo_capi::ffi::*;

/// The crate folder.
pub fn here() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

/// Where cargo put `libkeylo_capi.so` (beside this test binary).
pub fn lib_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.parent().expect("deps folder").to_path_buf()
}

/// Compiles the C (`-std=c99`) or C++ (`-std=c++17`) program `source` of this crate into
/// `exe` against `include/keylo.h` and `libkeylo_capi.so`, warnings as errors.
pub fn compile(source: &Path, exe: &Path) {
    let cpp = source.extension().is_some_and(|e| e == "cpp");
    let target = env!("KEYLO_TEST_TARGET");
    let compiler = cc::Build::new()
        .cpp(cpp)
        .cargo_metadata(false)
        .opt_level(1)
        .debug(false)
        .target(target)
        .host(target)
        .try_get_compiler()
        .expect("a C/C++ compiler");
    let flags: &[&str] = if cpp {
        &["-std=c++17", "-Wall", "-Wextra", "-Werror"]
    } else {
        &["-std=c99", "-Wall", "-Werror"]
    };
    let o = compiler
        .to_command()
        .args(flags)
        .arg("-I")
        .arg(here().join("include"))
        .arg(source)
        .arg("-o")
        .arg(exe)
        .arg("-L")
        .arg(lib_dir())
        .arg(format!("-Wl,-rpath,{}", lib_dir().display()))
        .args(["-lkeylo_capi", "-lm"])
        .output()
        .expect("the compiler runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `frames` frames of the simulated lab (OS1-64, 512 columns, more `source.` keys in
/// `extra`), each handed to `each`; the ground truth.
pub fn simulate_lab(
    frames: usize,
    extra: &[&str],
    mut each: impl FnMut(usize, keylo::LidarFrame),
) -> keylo::Trajectory {
    let mut raw = keylo::config::RawConfig::builtin();
    let count = format!("source.frames={frames}");
    let keys = [
        "source.kind=sim",
        "source.scene=lab",
        "source.sensor=os1-64",
        "source.columns=512",
        count.as_str(),
    ];
    for s in keys.iter().chain(extra) {
        raw.set(s).unwrap();
    }
    let registry = keylo::registry();
    let config = registry.resolve(&raw).unwrap();
    let mut source = keylo::build_source(&config, &registry).unwrap();
    let mut k = 0;
    while let Some(frame) = source.next_frame() {
        each(k, frame.unwrap());
        k += 1;
    }
    assert_eq!(k, frames);
    source.ground_truth().expect("simulator ground truth")
}

/// An empty `KeyloFrameStats` with its size set.
pub fn stats_out() -> KeyloFrameStats {
    KeyloFrameStats {
        size: std::mem::size_of::<KeyloFrameStats>() as u32,
        ..KeyloFrameStats::default()
    }
}

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
