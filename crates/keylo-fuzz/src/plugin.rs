//! Plugin descriptor tables (`KeyloPluginInfo`), built in memory from the input and checked
//! by the loader's own validation ([`Plugin::from_info`], what `Plugin::open` runs on the
//! table a library's `keylo_plugin_entry` returns), then registered.
//!
//! Input layout (every field read with [`Bytes`], zero once the input ends):
//! `abi_version` (1 byte; 0xff: 4 more bytes, little-endian, else the byte itself), `name`
//! and `version` ([`Bytes::c_string`]), a flags byte (bit 0: `kinds` is NULL), `kind_count`
//! (1 byte), then per kind: `stage` (as `abi_version`), `summary`, and one byte whose bits
//! 0..6 say which of `create`, `configure`, `destroy`, `detect`, `describe`, `downsample`,
//! `register_cloud` are non-NULL, and bit 7 whether the four SLAM hooks are (pointing at
//! stubs that are never called). The kinds are laid out as `abi_version` says: the shorter
//! version-1/2 element for those versions.

use std::ffi::{c_char, c_void};
use std::path::Path;
use std::sync::Arc;

use keylo_plugin::abi::*;
use keylo_plugin::host::{register_plugin, KindV2, Plugin};

/// A cursor over the input; reads past the end give zeros.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        let (first, rest) = self.0.split_first().map_or((0, &[][..]), |(f, r)| (*f, r));
        self.0 = rest;
        first
    }

    /// A small number, or (after 0xff) any `u32`.
    fn u32(&mut self) -> u32 {
        match self.u8() {
            0xff => u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()]),
            b => u32::from(b),
        }
    }

    /// A length byte (0xff: NULL) and that many bytes, which may hold NULs or invalid UTF-8;
    /// the string is NUL-terminated as the ABI requires.
    fn c_string(&mut self) -> Option<Vec<u8>> {
        let len = self.u8();
        if len == 0xff {
            return None;
        }
        let mut s: Vec<u8> = (0..len).map(|_| self.u8()).collect();
        s.push(0);
        Some(s)
    }
}

fn ptr(s: &Option<Vec<u8>>) -> *const c_char {
    s.as_ref().map_or(std::ptr::null(), |v| v.as_ptr().cast())
}

unsafe extern "C" fn create(_: *mut KeyloError) -> *mut c_void {
    std::ptr::null_mut()
}
unsafe extern "C" fn configure(_: *mut c_void, _: *const c_char, _: *mut KeyloError) -> i32 {
    KEYLO_ERR_INTERNAL
}
unsafe extern "C" fn destroy(_: *mut c_void) {}
unsafe extern "C" fn detect(
    _: *mut c_void,
    _: *const KeyloImage,
    _: *mut KeyloKeypoints,
    _: *mut KeyloError,
) -> i32 {
    KEYLO_ERR_INTERNAL
}
unsafe extern "C" fn describe(
    _: *mut c_void,
    _: *const KeyloImage,
    _: *const KeyloKeypoints,
    _: *mut KeyloKeypoints,
    _: *mut KeyloDescriptors,
    _: *mut KeyloError,
) -> i32 {
    KEYLO_ERR_INTERNAL
}
unsafe extern "C" fn downsample(
    _: *mut c_void,
    _: *const KeyloFrame,
    _: *const KeyloFeatures,
    _: *mut KeyloCloud,
    _: *mut KeyloError,
) -> i32 {
    KEYLO_ERR_INTERNAL
}
unsafe extern "C" fn register_cloud(
    _: *mut c_void,
    _: *const KeyloCloud,
    _: *mut KeyloRegistration,
    _: *mut KeyloError,
) -> i32 {
    KEYLO_ERR_INTERNAL
}

unsafe extern "C" fn matrix_hook(_: *mut c_void, _: *const f64, _: *mut KeyloError) -> i32 {
    KEYLO_ERR_INTERNAL
}
unsafe extern "C" fn reset(_: *mut c_void, _: *mut KeyloError) -> i32 {
    KEYLO_ERR_INTERNAL
}
unsafe extern "C" fn local_map(
    _: *mut c_void,
    _: *mut *const f64,
    _: *mut usize,
    _: *mut KeyloError,
) -> i32 {
    KEYLO_ERR_INTERNAL
}

/// A kind as read from the input, with the summary it points to.
fn kind(b: &mut Bytes, summaries: &mut Vec<Option<Vec<u8>>>) -> KeyloPluginKind {
    let stage = b.u32();
    let summary = b.c_string();
    let fns = b.u8();
    let bit = |i: u8| fns & (1 << i) != 0;
    let kind = KeyloPluginKind {
        stage,
        summary: ptr(&summary),
        create: bit(0).then_some(create as _),
        configure: bit(1).then_some(configure as _),
        destroy: bit(2).then_some(destroy as _),
        detect: bit(3).then_some(detect as _),
        describe: bit(4).then_some(describe as _),
        downsample: bit(5).then_some(downsample as _),
        register_cloud: bit(6).then_some(register_cloud as _),
        set_motion_prior: bit(7).then_some(matrix_hook as _),
        set_pose: bit(7).then_some(matrix_hook as _),
        reset: bit(7).then_some(reset as _),
        local_map: bit(7).then_some(local_map as _),
    };
    summaries.push(summary);
    kind
}

/// A descriptor table built from `data` (layout above), validated and registered.
pub fn plugin_table(data: &[u8]) {
    let mut b = Bytes(data);
    let abi_version = b.u32();
    let (name, version) = (b.c_string(), b.c_string());
    let null_kinds = b.u8() & 1 != 0;
    let count = usize::from(b.u8());
    let mut summaries = Vec::with_capacity(count);
    let kinds: Vec<KeyloPluginKind> = (0..count).map(|_| kind(&mut b, &mut summaries)).collect();
    // The array as a plugin of `abi_version` lays it out.
    let old: Vec<KindV2> = kinds.iter().map(KindV2::from).collect();
    let array: *const KeyloPluginKind = if null_kinds {
        std::ptr::null()
    } else if abi_version <= 2 {
        old.as_ptr().cast()
    } else {
        kinds.as_ptr()
    };
    let info = KeyloPluginInfo {
        abi_version,
        name: ptr(&name),
        version: ptr(&version),
        kinds: array,
        kind_count: kinds.len(),
    };
    // SAFETY: `info` is a complete `KeyloPluginInfo`; its strings are NULL or NUL-terminated
    // and `kinds` is NULL or holds `kind_count` entries, all alive until the end of this
    // function. The function pointers are never called.
    let checked = unsafe { Plugin::from_info(&info, Path::new("fuzz-plugin.so")) };
    if let Ok(plugin) = checked {
        assert!(!plugin.kinds.is_empty() && !plugin.name.is_empty());
        let mut registry = keylo_core::Registry::default();
        register_plugin(&mut registry, &Arc::new(plugin));
    }
    drop((summaries, name, version, kinds, old));
}
