//! The loader: finds plugin libraries, checks their tables and registers their kinds.

mod instance;
mod library;
mod register;
mod search;
mod views;

pub use instance::{Instance, RegistrarInstance};
pub use library::{Kind, KindV2, Plugin, Stage, ENTRY_SYMBOL, SUPPORTED_ABI};
pub use register::{load_for_config, referenced, register_plugin, search_path, KIND_PREFIX};
pub use search::{file_names, SearchPath, CONFIG_DIRS, DEFAULT_DIR, PLUGIN_PATH_ENV};
