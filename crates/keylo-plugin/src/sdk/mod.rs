//! The Rust SDK: implement a keylo stage trait and [`FromConfig`], add one
//! [`export_plugin!`](crate::export_plugin) line, build as `cdylib`.
//!
//! ```ignore
//! struct Corners { threshold: f32 }
//! impl keylo_plugin::FromConfig for Corners { type Params = Params; fn from_params(p: Params) -> Result<Self, String> { … } }
//! impl keylo_core::Detector for Corners { fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> { … } }
//! keylo_plugin::export_plugin! { name: "corners", version: "0.1.0", detector: Corners => "FAST-like corners" }
//! ```
//!
//! Every call is wrapped in `catch_unwind`: a panic becomes a [`KEYLO_ERR_PANIC`] error with
//! the panic message, never an abort across the C boundary.

mod hooks;
mod inputs;
mod kinds;
mod shims;

use std::ffi::{c_char, CString};

use serde::de::DeserializeOwned;

use crate::abi::*;

pub use inputs::{features_from_abi, frame_from_abi, image_from_abi, scan_from_abi};
pub use kinds::{descriptor, detector, downsampler, registrar};

/// How a plugin backend is made from its config table.
pub trait FromConfig: Sized + Send + 'static {
    /// The parameters: a serde struct, usually `#[serde(default, deny_unknown_fields)]`.
    type Params: DeserializeOwned;
    /// The backend for `params`; the error names what is wrong.
    fn from_params(params: Self::Params) -> Result<Self, String>;
}

/// One kind of an exported plugin, before its strings are fixed in memory.
pub struct KindSpec {
    /// The stage's run function and the common functions, `summary` left NULL.
    pub kind: KeyloPluginKind,
    pub summary: String,
}

/// The descriptor table of a plugin with the strings it points to. Built once, by the
/// `keylo_plugin_entry` function [`export_plugin!`](crate::export_plugin) writes, and kept
/// for the life of the library.
pub struct Exported {
    info: KeyloPluginInfo,
    _kinds: Vec<KeyloPluginKind>,
    _strings: Vec<CString>,
}

// SAFETY: an `Exported` is never changed after `new`; its raw pointers point into its own
// heap buffers (the `CString`s and the kinds `Vec`), which live as long as it does.
unsafe impl Send for Exported {}
// SAFETY: as above: shared references only read.
unsafe impl Sync for Exported {}

impl Exported {
    /// The table for plugin `name` at `version` offering `kinds`.
    pub fn new(name: &str, version: &str, kinds: Vec<KindSpec>) -> Self {
        let cstring = |s: &str| CString::new(s.replace('\0', " ")).unwrap_or_default();
        let mut strings = vec![cstring(name), cstring(version)];
        let mut table = Vec::with_capacity(kinds.len());
        for spec in kinds {
            let summary = cstring(&spec.summary);
            let mut kind = spec.kind;
            kind.summary = summary.as_ptr();
            strings.push(summary);
            table.push(kind);
        }
        let info = KeyloPluginInfo {
            abi_version: KEYLO_PLUGIN_ABI_VERSION,
            name: strings[0].as_ptr(),
            version: strings[1].as_ptr(),
            kinds: table.as_ptr(),
            kind_count: table.len(),
        };
        Self {
            info,
            _kinds: table,
            _strings: strings,
        }
    }

    /// The table, as `keylo_plugin_entry` returns it.
    pub fn info(&self) -> *const KeyloPluginInfo {
        &self.info
    }
}

/// The null-summary kind skeleton the stage helpers fill in.
fn blank_kind(stage: u32) -> KeyloPluginKind {
    KeyloPluginKind {
        stage,
        summary: std::ptr::null::<c_char>(),
        create: None,
        configure: None,
        destroy: None,
        detect: None,
        describe: None,
        downsample: None,
        register_cloud: None,
        set_motion_prior: None,
        set_pose: None,
        reset: None,
        local_map: None,
    }
}

/// Exports a Rust plugin: defines the `keylo_plugin_entry` symbol returning its table.
///
/// ```ignore
/// keylo_plugin::export_plugin! {
///     name: "range-edges",
///     version: env!("CARGO_PKG_VERSION"),
///     detector: RangeEdges => "depth-discontinuity and curvature keypoints on the range image",
/// }
/// ```
///
/// Stages: `detector`, `descriptor`, `downsampler`, `registrar` (each at most once); the type
/// implements [`FromConfig`] and the keylo trait of that stage.
#[macro_export]
macro_rules! export_plugin {
    (name: $name:expr, version: $version:expr $(, $stage:ident : $ty:ty => $summary:expr)* $(,)?) => {
        /// The keylo plugin entry point (see `keylo_plugin.h`).
        #[no_mangle]
        pub extern "C" fn keylo_plugin_entry() -> *const $crate::abi::KeyloPluginInfo {
            static EXPORTED: ::std::sync::OnceLock<$crate::sdk::Exported> =
                ::std::sync::OnceLock::new();
            EXPORTED
                .get_or_init(|| {
                    $crate::sdk::Exported::new(
                        $name,
                        $version,
                        vec![$($crate::sdk::$stage::<$ty>($summary)),*],
                    )
                })
                .info()
        }
    };
}
