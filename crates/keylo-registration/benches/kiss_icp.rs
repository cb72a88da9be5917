//! Hot paths of the KISS-ICP registrar on the committed parity frames (OS1-64×512 road scans):
//! upstream-order voxel downsampling vs plain scan-order downsampling, and registering a
//! sequence of frames. Run: `cargo bench -p keylo-registration`.

use std::path::Path;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use keylo_core::{PointCloud, Registrar};
use keylo_registration::voxel::{downsample, UpstreamGrid};
use keylo_registration::{KissIcp, KissIcpConfig};
use nalgebra::Point3;

fn frames() -> Vec<Vec<Point3<f64>>> {
    let dir =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/kiss_icp_parity/velodyne");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(Result::ok).map(|e| e.path()).collect())
        .unwrap_or_default();
    files.sort();
    files
        .iter()
        .filter_map(|f| std::fs::read(f).ok())
        .map(|bytes| {
            bytes
                .chunks_exact(16)
                .map(|c| {
                    let v = |k: usize| {
                        f64::from(f32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]))
                    };
                    Point3::new(v(0), v(4), v(8))
                })
                .collect()
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let frames = frames();
    let Some(first) = frames.first() else {
        eprintln!("parity fixture frames missing; nothing to bench");
        return;
    };
    let mut grid = UpstreamGrid::default();
    let mut out = Vec::new();
    c.bench_function("voxel downsample 0.5 m, upstream order", |b| {
        b.iter(|| grid.downsample_into(first, 0.5, &mut out))
    });
    c.bench_function("voxel downsample 0.5 m, scan order", |b| {
        b.iter(|| downsample(first, 0.5))
    });
    c.bench_function("kiss-icp: register 20 frames", |b| {
        b.iter_batched(
            || KissIcp::new(KissIcpConfig::default()).map_err(|e| e.to_string()),
            |registrar| {
                if let Ok(mut r) = registrar {
                    for (i, pts) in frames.iter().enumerate() {
                        let _ = r.register(&PointCloud::from_points(i as f64, pts.clone()));
                    }
                }
            },
            BatchSize::LargeInput,
        )
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
