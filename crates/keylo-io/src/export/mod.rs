//! Writing frames as files other tools read: point clouds (KITTI `.bin`, PLY, PCD; see
//! [`points`]) and channel images (PNG; see [`png_image`]).

pub mod cloud_file;
pub mod pcd;
pub mod ply;
pub mod png_image;
pub mod points;

pub use cloud_file::{write_xyzi, CloudFormat};
pub use points::{ExportField, ExportPoints};
