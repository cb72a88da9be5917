//! Hot paths of the NDT aligner on the committed real pair (`tests/fixtures/ndt`): building the
//! target (voxel Gaussians + k-d tree), one score/gradient/Hessian evaluation per neighbour
//! search mode, and a whole alignment as PCL's `align` (eps 0.001, 6 iterations).
//! Run: `cargo bench -p keylo-registration --bench ndt`.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use keylo_registration::ndt::score::{derivatives, Gauss};
use keylo_registration::ndt::{align, AlignSettings, GridSettings, NdtTarget, NeighbourSearch};
use nalgebra::{Isometry3, Point3, Vector6};

fn load(name: &str) -> Vec<Point3<f64>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/fixtures/ndt")
        .join(name);
    std::fs::read(path)
        .unwrap_or_default()
        .chunks_exact(16)
        .map(|c| {
            let v = |k: usize| f64::from(f32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]));
            Point3::new(v(0), v(4), v(8))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let (source, target) = (load("real_source.bin"), load("real_target.bin"));
    let grid = GridSettings::default();
    let Ok(radius) = NdtTarget::new(&target, &grid, NeighbourSearch::Radius) else {
        eprintln!("NDT fixture pair missing; nothing to bench");
        return;
    };
    c.bench_function("ndt target build (69k points, 1 m)", |b| {
        b.iter(|| NdtTarget::new(&target, &grid, NeighbourSearch::Radius))
    });
    let p = Vector6::new(0.3, 0.05, 0.0, 0.0, 0.0, -0.01);
    let gauss = Gauss::new(0.55, 1.0);
    for search in [
        NeighbourSearch::Radius,
        NeighbourSearch::Direct7,
        NeighbourSearch::Direct1,
    ] {
        let Ok(t) = NdtTarget::new(&target, &grid, search) else {
            continue;
        };
        c.bench_function(&format!("ndt derivatives with Hessian ({search:?})"), |b| {
            b.iter(|| derivatives(&t, &source, &p, gauss, true))
        });
    }
    let settings = AlignSettings {
        transformation_epsilon: 0.001,
        ..AlignSettings::default()
    };
    c.bench_function("ndt align real pair (radius, eps 0.001)", |b| {
        b.iter(|| align(&radius, &source, &Isometry3::identity(), &settings))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
