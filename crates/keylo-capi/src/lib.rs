//! The C API of keylo (`include/keylo.h`, library `libkeylo_capi.so`): create a pipeline from
//! a TOML config, push organised frames or point clouds, read the pose and the registered
//! cloud, free. See `tests/embed.c` for a complete C program.

mod embedded;
mod error;
pub mod ffi;

pub use embedded::Embedded;
pub use error::CapiError;
