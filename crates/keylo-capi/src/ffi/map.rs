//! Saving a global map of the frames pushed (docs/maps.md).

use std::ffi::{c_char, CStr};

use super::handles::with;
use super::types::KeyloPipeline;
use crate::CapiError;

/// A NUL-terminated UTF-8 argument; an error naming `what` when it is NULL or not UTF-8.
///
/// # Safety
/// `s` is NULL or NUL-terminated.
unsafe fn text_arg<'a>(s: *const c_char, what: &str) -> Result<&'a str, CapiError> {
    if s.is_null() {
        return Err(CapiError::Argument(format!("{what} is NULL")));
    }
    // SAFETY: NUL-terminated per the contract.
    unsafe { CStr::from_ptr(s) }
        .to_str()
        .map_err(|_| CapiError::Argument(format!("{what} is not UTF-8")))
}

/// Saves a global map of the frames pushed from now on in the folder `dir`: the world-frame
/// cloud, voxelised (map.ply, map.pcd), and keyframes with their clouds, keypoints and
/// descriptors. `settings`: TOML with the keys of a config's `[map]` table (e.g.
/// `"voxel_size = 0.1"`), or NULL for the defaults. `keylo_pipeline_finish_map` (or
/// `keylo_pipeline_free`) completes it. Returns 0, or -1 (bad settings, a folder that cannot
/// be written).
///
/// # Safety
/// `dir` NUL-terminated; `settings` NULL or NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_save_map(
    p: *mut KeyloPipeline,
    dir: *const c_char,
    settings: *const c_char,
) -> i32 {
    with(p, |e| {
        // SAFETY: forwarded from the caller.
        let dir = unsafe { text_arg(dir, "dir") }?;
        let table: toml::Table = if settings.is_null() {
            toml::Table::new()
        } else {
            // SAFETY: forwarded from the caller.
            let text = unsafe { text_arg(settings, "settings") }?;
            toml::from_str(text)
                .map_err(|err| CapiError::Argument(format!("settings: not TOML: {err}")))?
        };
        let settings = keylo::map::MapConfig::from_table(&table, "settings")
            .map_err(|err| CapiError::Frontend(err.into()))?;
        e.save_map(dir, settings)
    })
}

/// Completes the map `keylo_pipeline_save_map` started: writes its cloud and map.json.
/// Returns 0 (also when no map was being saved), or -1.
///
/// # Safety
/// None beyond the rules in the header.
#[no_mangle]
pub unsafe extern "C" fn keylo_pipeline_finish_map(p: *mut KeyloPipeline) -> i32 {
    with(p, |e| e.finish_map())
}
