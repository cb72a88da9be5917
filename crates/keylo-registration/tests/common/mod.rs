//! Helpers shared by the PCL parity tests.

use std::path::{Path, PathBuf};

use nalgebra::Point3;

/// `tests/fixtures/` of the repository.
pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures")
}

/// A KITTI `.bin` cloud (float32 x y z i) of the fixtures.
pub fn load_bin(path: &Path) -> Vec<Point3<f64>> {
    let bytes = std::fs::read(path).unwrap();
    bytes
        .chunks_exact(16)
        .map(|c| {
            let f = |i: usize| f64::from(f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]));
            Point3::new(f(0), f(4), f(8))
        })
        .collect()
}
