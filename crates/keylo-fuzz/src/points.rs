//! PLY and PCD point files, read as source kinds `ply` and `pcd`.

use keylo_core::BuildContext;
use keylo_io::point_files::{PointFilesConfig, PointFilesSource, PointFormat};

use crate::scratch;

/// A `.ply` file: its fields (as `keylo info` lists them), then the file as a one-frame
/// folder of source kind `ply`.
pub fn ply(data: &[u8]) {
    point_file(data, PointFormat::Ply);
}

/// A `.pcd` file, as [`ply`] does.
pub fn pcd(data: &[u8]) {
    point_file(data, PointFormat::Pcd);
}

fn point_file(data: &[u8], format: PointFormat) {
    let name = format!("cloud.{}", format.extension());
    scratch::with_files(&[(&name, data)], true, |dir| {
        let _ = format.fields(&dir.join(&name));
        let config = PointFilesConfig {
            path: name.clone(),
            ..PointFilesConfig::default()
        };
        let ctx = BuildContext {
            base_dir: dir.to_path_buf(),
            ..Default::default()
        };
        if let Ok(mut source) = PointFilesSource::open(format, &config, &ctx) {
            crate::drain(&mut source);
        }
    });
}
