//! The same input and config give bit-identical trajectories, across runs and thread counts
//! (fixed hashers, chunk-ordered parallel sums, per-pixel noise streams in the simulator).

use keylo::config::RawConfig;
use keylo::Pipeline;

const RAW: &str = "[source]\nscene = 'road'\nframes = 15\n";

const KEYPOINTS: &str = "[source]\nscene = 'road'\nframes = 15\n\
    [image]\nkind = 'lidar'\nimages = ['signal', 'range']\n\
    [detector]\nkind = 'orb'\n\
    [downsampler]\nkind = 'keypoint-neighbourhood'\nwindows = '4_7'\non_too_few = 'all-points'\n";

fn run_with_threads(threads: usize) -> Vec<[u64; 7]> {
    run_config(RAW, threads)
}

fn run_config(text: &str, threads: usize) -> Vec<[u64; 7]> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let registry = keylo::registry();
        let raw = RawConfig::parse("test", text).unwrap();
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

#[test]
fn keypoint_pipeline_is_bit_identical_across_runs_and_thread_counts() {
    let one = run_config(KEYPOINTS, 2);
    assert_eq!(one.len(), 15);
    assert_eq!(one, run_config(KEYPOINTS, 2), "two keypoint runs differ");
    assert_eq!(one, run_config(KEYPOINTS, 1), "two threads and one differ");
    assert_eq!(
        one,
        run_config(KEYPOINTS, 3),
        "two threads and three differ"
    );
}

#[test]
fn ndt_is_bit_identical_across_thread_counts() {
    let ndt = format!("{RAW}[registrar]\nkind = 'ndt'\n");
    let one = run_config(&ndt, 1);
    assert_eq!(one.len(), 15);
    assert_eq!(
        one,
        run_config(&ndt, 3),
        "NDT on one thread and on three differ"
    );
}

#[test]
fn hybrid_is_bit_identical_across_thread_counts() {
    // Point-to-plane residuals with the per-frame normal cache, keypoint pairs with their
    // covariances and the two-stage gate: every parallel part is chunk-ordered.
    let hybrid = "[source]\nscene = 'corridor'\nframes = 12\n\
        [image]\nkind = 'lidar'\nimages = ['signal', 'range']\n\
        [detector]\nkind = 'fast'\nthreshold = 10\n\
        [descriptor]\nkind = 'freak'\n\
        [downsampler]\nkind = 'passthrough'\n\
        [registrar]\nkind = 'hybrid'\n";
    let one = run_config(hybrid, 1);
    assert_eq!(one.len(), 12);
    assert_eq!(
        one,
        run_config(hybrid, 3),
        "hybrid on one thread and on three differ"
    );
}

#[test]
fn gicp_is_bit_identical_across_runs_and_thread_counts() {
    // Both modes and both costs: covariances, pairing and the normal equations are
    // chunk-ordered, so one thread and three give the same bits.
    for registrar in [
        "kind = 'gicp'",
        "kind = 'gicp'\ncost = 'point-to-plane'",
        "kind = 'gicp'\nmode = 'frame-to-frame'\nvoxel_size = 0.5",
    ] {
        let gicp = format!("{RAW}[registrar]\n{registrar}\n");
        let one = run_config(&gicp, 1);
        assert_eq!(one.len(), 15);
        assert_eq!(one, run_config(&gicp, 1), "{registrar}: two runs differ");
        assert_eq!(
            one,
            run_config(&gicp, 3),
            "{registrar}: one thread and three differ"
        );
    }
}
