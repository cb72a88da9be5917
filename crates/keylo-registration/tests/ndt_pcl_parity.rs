//! keylo's NDT against PCL 1.13's `NormalDistributionsTransform` on committed fixture pairs
//! (real outdoor scans and simulated frames; `tests/fixtures/ndt/README.md` says how each was
//! made): the same pose within 1 cm / 0.1° and the same iteration count (± 1).

use std::path::PathBuf;

use keylo_registration::ndt::{align, AlignSettings, GridSettings, NdtTarget, NeighbourSearch};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};

mod common;

fn fixtures() -> PathBuf {
    common::fixtures().join("ndt")
}

fn load(name: &str) -> Vec<Point3<f64>> {
    common::load_bin(&fixtures().join(name))
}

/// The known transform of the real pair (`small_gicp_T_target_source.txt`).
const REAL_T: [f64; 3] = [0.488882, 0.121214, -0.0253342];

struct Case {
    source: String,
    target: String,
    resolution: f64,
    settings: AlignSettings,
    pose: Isometry3<f64>,
    iterations: usize,
    line: String,
}

fn cases() -> Vec<Case> {
    let text = std::fs::read_to_string(fixtures().join("pcl_golden.txt")).unwrap();
    text.lines()
        .map(|line| {
            let (args, result) = line.split_once(" => ").unwrap();
            let a: Vec<&str> = args.split_whitespace().collect();
            let opt = |k: &str| -> f64 {
                let i = a.iter().position(|x| *x == k).unwrap();
                a[i + 1].parse().unwrap()
            };
            let r: Vec<&str> = result.split_whitespace().collect();
            let v: Vec<f64> = r[..7].iter().map(|x| x.parse().unwrap()).collect();
            let q = UnitQuaternion::from_quaternion(Quaternion::new(v[6], v[3], v[4], v[5]));
            Case {
                source: a[0].into(),
                target: a[1].into(),
                resolution: opt("--res"),
                settings: AlignSettings {
                    step_size: opt("--step"),
                    transformation_epsilon: opt("--eps"),
                    max_iterations: opt("--iters") as usize,
                    ..AlignSettings::default()
                },
                pose: Isometry3::from_parts(Translation3::new(v[0], v[1], v[2]), q),
                iterations: r[8].parse().unwrap(),
                line: line.into(),
            }
        })
        .collect()
}

fn target(name: &str, resolution: f64, search: NeighbourSearch) -> NdtTarget {
    let grid = GridSettings {
        resolution,
        ..GridSettings::default()
    };
    NdtTarget::new(&load(name), &grid, search).unwrap()
}

#[test]
fn poses_match_pcl_within_1cm_and_0_1_degree() {
    let cases = cases();
    assert!(cases.len() >= 6);
    for c in cases {
        let t = target(&c.target, c.resolution, NeighbourSearch::Radius);
        let r = align(&t, &load(&c.source), &Isometry3::identity(), &c.settings).unwrap();
        let d = c.pose.inverse() * r.pose;
        let (dt, dr) = (d.translation.vector.norm(), d.rotation.angle().to_degrees());
        println!(
            "{} | keylo {} iterations, Δt {dt:.6} m, Δr {dr:.5}°",
            c.line, r.iterations
        );
        assert!(dt < 0.01 && dr < 0.1, "{}: Δt {dt} m Δr {dr}°", c.line);
        assert!(
            r.iterations.abs_diff(c.iterations) <= 1,
            "{}: {} iterations",
            c.line,
            r.iterations
        );
        assert!(
            r.iterations == c.settings.max_iterations || r.converged,
            "{}",
            c.line
        );
    }
}

#[test]
fn pcl_convergence_rule_stops_a_coarse_epsilon_after_one_short_step() {
    // PROVENANCE.md: with ε = 0.01 PCL stops after one step of ≤ 0.1 m (its rule compares the
    // squared step translation with ε); keylo stops there too, far from the 0.49 m answer.
    let t = target("real_target.bin", 1.0, NeighbourSearch::Radius);
    let source = load("real_source.bin");
    let coarse = AlignSettings {
        transformation_epsilon: 0.01,
        ..AlignSettings::default()
    };
    let r = align(&t, &source, &Isometry3::identity(), &coarse).unwrap();
    assert_eq!(r.iterations, 1);
    assert!(r.converged);
    assert!(r.pose.translation.vector.norm() <= 0.1 + 1e-9);
    let tight = AlignSettings {
        transformation_epsilon: 1e-4,
        ..AlignSettings::default()
    };
    let r = align(&t, &source, &Isometry3::identity(), &tight).unwrap();
    let err = (r.pose.translation.vector - Vector3::from(REAL_T)).norm();
    assert!(err < 0.02, "{}", r.pose);
}

#[test]
fn direct_search_modes_recover_the_real_transform_within_their_basins() {
    let tight = AlignSettings {
        transformation_epsilon: 1e-4,
        ..AlignSettings::default()
    };
    let source = load("real_source.bin");
    // DIRECT7 from identity (0.5 m away); DIRECT1 (one voxel, narrow basin) from 10 cm away.
    let near = Isometry3::translation(0.42, 0.06, 0.0);
    for (search, guess) in [
        (NeighbourSearch::Direct7, Isometry3::identity()),
        (NeighbourSearch::Direct1, near),
    ] {
        let t = target("real_target.bin", 1.0, search);
        let r = align(&t, &source, &guess, &tight).unwrap();
        let err = (r.pose.translation.vector - Vector3::from(REAL_T)).norm();
        println!("{search:?}: {} iterations, error {err:.4} m", r.iterations);
        assert!(err < 0.03, "{search:?}: {}", r.pose);
    }
}
