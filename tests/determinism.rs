//! The same input and config give bit-identical trajectories, across runs and thread counts
//! (fixed hashers, chunk-ordered parallel sums, per-pixel noise streams in the simulator).

use keylo::config::RawConfig;
use keylo::Pipeline;

fn run_with_threads(threads: usize) -> Vec<[u64; 7]> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let registry = keylo::registry();
        let raw = RawConfig::parse("test", "[source]\nscene = 'road'\nframes = 15\n").unwrap();
        let config = registry.resolve(&raw).unwrap();
        let mut pipeline = Pipeline::build(&config, &registry).unwrap();
        let mut poses = Vec::new();
        while let Some(r) = pipeline.step() {
            let p = r.unwrap().pose;
            let t = p.translation.vector;
            let q = p.rotation.coords;
            poses.push([t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(f64::to_bits));
        }
        poses
    })
}

#[test]
fn trajectories_are_bit_identical_across_runs_and_thread_counts() {
    let one = run_with_threads(1);
    assert_eq!(one.len(), 15);
    assert_eq!(one, run_with_threads(1), "two runs on one thread differ");
    assert_eq!(
        one,
        run_with_threads(3),
        "one thread and three threads differ"
    );
}
