//! Writing frames as files other tools read: point clouds (KITTI `.bin`, PLY, PCD; see
//! [`points`]) and channel images (PNG; see [`png_image`]).

pub mod pcd;
pub mod ply;
pub mod png_image;
pub mod points;

pub use points::{ExportField, ExportPoints};
