//! Folders of point files as sources: `kind = "ply"` (Stanford PLY, ascii and binary) and
//! `kind = "pcd"` (PCL's PCD, ascii, binary and binary_compressed). One file is one frame;
//! files are read in natural order of their names, one per `next_frame`. Field names,
//! units and time stamps: `docs/formats.md`.

mod config;
mod source;

pub(crate) use config::check_frame_rate;
pub use config::{PcdSourceConfig, PlySourceConfig, PointFilesConfig};
pub use source::{PointFilesSource, PointFormat};

/// True when `path` is a `.ply` file or a folder holding `.ply` files.
pub fn is_ply_data(path: &std::path::Path) -> bool {
    PointFormat::Ply.probe(path)
}

/// True when `path` is a `.pcd` file or a folder holding `.pcd` files.
pub fn is_pcd_data(path: &std::path::Path) -> bool {
    PointFormat::Pcd.probe(path)
}

/// Builds a `kind = "ply"` source (the registry's constructor).
pub fn build_ply(
    config: PlySourceConfig,
    ctx: &keylo_core::BuildContext,
) -> Result<Box<dyn keylo_core::ImageSource>, keylo_core::CoreError> {
    Ok(Box::new(PointFilesSource::open(
        PointFormat::Ply,
        &config,
        ctx,
    )?))
}

/// Builds a `kind = "pcd"` source (the registry's constructor).
pub fn build_pcd(
    config: PcdSourceConfig,
    ctx: &keylo_core::BuildContext,
) -> Result<Box<dyn keylo_core::ImageSource>, keylo_core::CoreError> {
    Ok(Box::new(PointFilesSource::open(
        PointFormat::Pcd,
        &config,
        ctx,
    )?))
}
