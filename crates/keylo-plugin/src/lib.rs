//! keylo plugins over a stable C ABI.
//!
//! - [`abi`]: the `#[repr(C)]` types of `include/keylo_plugin.h` (ABI version
//!   [`abi::KEYLO_PLUGIN_ABI_VERSION`]).
//! - [`sdk`]: write a plugin in Rust — implement a keylo stage trait and [`FromConfig`], add
//!   one [`export_plugin!`] line, build as `cdylib`.
//! - [`host`]: the loader keylo uses — `kind = "plugin:NAME"` in any of `[detector]`,
//!   `[descriptor]`, `[downsampler]`, `[registrar]`.
//!
//! See docs/plugins.md.

pub mod abi;
pub mod convert;
mod error;
pub mod host;
pub mod sdk;

pub use error::PluginError;
pub use host::{load_for_config, Plugin, SearchPath};
pub use sdk::FromConfig;
