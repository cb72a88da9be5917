//! Making, questioning and freeing a pipeline.

use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::TryLockError;

use super::handles::{self, panic_text};
use keylo::config::Trust;

use super::types::{KeyloPipeline, KEYLO_TRUST_PLUGINS};
use crate::{CapiError, Embedded};

/// The keylo version, a static NUL-terminated string.
#[no_mangle]
pub extern "C" fn keylo_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// A pipeline from a TOML config (the format of `keylo run` configs; `[source]` is not used
/// except `[source.projection]` for `keylo_pipeline_push_points`). Relative paths resolve
/// against `base_dir` (NULL: the current folder). On failure: NULL, and the message is written
/// to `error` (`error_len` bytes, NUL-terminated) when it is not NULL. A config naming
/// libraries of its own (`[plugins] dirs`, `onnxruntime`) is refused: see
/// `keylo_pipeline_new_with_flags`.
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
    // SAFETY: the caller's contract is this function's.
    unsafe { keylo_pipeline_new_with_flags(toml, base_dir, 0, error, error_len) }
}

/// `keylo_pipeline_new` with `flags`: 0, or `KEYLO_TRUST_PLUGINS` to load the libraries the
/// config names itself (their code runs; only for configs you trust). Unknown bits are an
/// error.
///
/// # Safety
/// As `keylo_pipeline_new`.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_new_with_flags(
    toml: *const c_char,
    base_dir: *const c_char,
    flags: u32,
    error: *mut c_char,
    error_len: usize,
) -> *mut KeyloPipeline {
    let made = catch_unwind(AssertUnwindSafe(|| {
        if toml.is_null() {
            return Err(CapiError::Argument("toml is NULL".into()));
        }
        if flags & !KEYLO_TRUST_PLUGINS != 0 {
            return Err(CapiError::Argument(format!(
                "flags {flags:#x}: unknown bits (expected 0 or KEYLO_TRUST_PLUGINS)"
            )));
        }
        let trust = Trust::opted_in(flags & KEYLO_TRUST_PLUGINS != 0);
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
        Embedded::new(text, &base, trust)
    }))
    .unwrap_or_else(|e| Err(CapiError::Panic(panic_text(e))));
    match made {
        Ok(inner) => handles::insert(inner),
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

/// Why the last call on `p` failed ("" after a success); for a NULL, freed or unknown handle,
/// why it is refused. Valid until the next call on `p`.
///
/// # Safety
/// None beyond the rules in the header: any value of `p` is answered.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_error(p: *const KeyloPipeline) -> *const c_char {
    let Some(slot) = handles::lookup(p) else {
        return handles::refusal(p).as_ptr();
    };
    // The text lives in the slot, which the table keeps until `keylo_pipeline_free`; only the
    // next call on `p` changes it.
    let text = match slot.try_lock() {
        Ok(state) => state.error.as_ptr(),
        Err(TryLockError::WouldBlock) => c"the pipeline is busy in another thread".as_ptr(),
        Err(TryLockError::Poisoned(e)) => e.into_inner().error.as_ptr(),
    };
    text
}

/// Frees a pipeline; waits for a call running on it in another thread. NULL, a handle
/// already freed, or one keylo never made, is ignored.
///
/// # Safety
/// None beyond the rules in the header: any value of `p` is accepted.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_free(p: *mut KeyloPipeline) {
    // A panic in a stage's destructor must not cross the C boundary.
    let _ = catch_unwind(AssertUnwindSafe(|| handles::remove(p)));
}
