//! `examples/slam_loop.cpp`, compiled as C++17 against `include/keylo.h` and
//! `libkeylo_capi.so`, runs keylo as the front end of a minimal SLAM loop on a KITTI-style
//! folder (simulated scans written as `.bin`), with and without a motion prior, and its poses
//! follow the simulator's ground truth.

mod common;

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use common::{here, lib_dir};
use keylo::Pose;

const FRAMES: usize = 12;

/// Simulated lab scans written as KITTI `.bin` files (every valid point, x y z signal) into
/// `dir/scans`; the ground truth relative to the first frame.
fn kitti_folder(dir: &Path) -> Vec<Pose> {
    std::fs::create_dir_all(dir.join("scans")).unwrap();
    let truth = common::simulate_lab(FRAMES, &["source.start_ramp_s=0"], |k, frame| {
        let mut bytes = Vec::new();
        for (i, p) in frame.points.iter().enumerate() {
            if frame.valid[i] {
                for v in [p.x, p.y, p.z, frame.signal[i]] {
                    bytes.extend(v.to_le_bytes());
                }
            }
        }
        std::fs::write(dir.join(format!("scans/{k:06}.bin")), bytes).unwrap();
    });
    truth
        .poses
        .iter()
        .map(|p| truth.poses[0].inverse() * p)
        .collect()
}

/// KITTI pose lines (row-major 3x4).
fn kitti_lines(poses: &[Pose]) -> String {
    let mut out = String::new();
    for p in poses {
        let m = p.to_homogeneous();
        let v: Vec<String> = (0..12)
            .map(|i| format!("{:.9}", m[(i / 4, i % 4)]))
            .collect();
        writeln!(out, "{}", v.join(" ")).unwrap();
    }
    out
}

/// Runs the program; the translation of every pose and the whole output.
fn run(exe: &Path, dir: &Path, prior: Option<&Path>) -> (Vec<[f64; 3]>, String) {
    let mut cmd = Command::new(exe);
    cmd.env("LD_LIBRARY_PATH", lib_dir())
        .arg(dir.join("keylo.toml"))
        .arg(dir.join("scans"));
    if let Some(p) = prior {
        cmd.arg(p);
    }
    let o = cmd.output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let poses = text
        .lines()
        .filter_map(|l| l.strip_prefix("pose "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [v[4], v[8], v[12]]
        })
        .collect();
    (poses, text)
}

fn max_error(est: &[[f64; 3]], truth: &[Pose]) -> f64 {
    est.iter()
        .zip(truth)
        .map(|(e, t)| (nalgebra::Vector3::from(*e) - t.translation.vector).norm())
        .fold(0.0, f64::max)
}

#[test]
fn cpp_slam_loop_runs_on_a_kitti_folder_with_and_without_a_prior() {
    let dir = tempfile::tempdir().unwrap();
    let truth = kitti_folder(dir.path());
    std::fs::write(
        dir.path().join("keylo.toml"),
        "[registrar]\nkind = \"kiss-icp\"\nmax_range = 30.0\n",
    )
    .unwrap();
    let prior = dir.path().join("prior.txt");
    std::fs::write(&prior, kitti_lines(&truth)).unwrap();
    let exe = dir.path().join("slam_loop");
    common::compile(&here().join("examples/slam_loop.cpp"), &exe);
    let travelled = truth[FRAMES - 1].translation.vector.norm();
    assert!(
        travelled > 0.3,
        "the simulated sensor moves ({travelled} m)"
    );
    for prior in [None, Some(prior.as_path())] {
        let (est, text) = run(&exe, dir.path(), prior);
        assert_eq!(est.len(), FRAMES, "{text}");
        let err = max_error(&est, &truth);
        eprintln!("prior {prior:?}: largest error {err:.4} m over {travelled:.2} m");
        assert!(
            err < 0.1,
            "prior {prior:?}: {err} m off the ground truth\n{text}"
        );
        let keyframes = text.lines().filter(|l| l.starts_with("keyframe ")).count();
        assert!(keyframes >= 2, "{text}");
        let map: usize = text
            .lines()
            .find_map(|l| l.strip_prefix("map "))
            .and_then(|n| n.parse().ok())
            .unwrap_or(0);
        assert!(map > 1000, "{text}");
    }
    // Bad input: a missing folder and a truncated scan are errors naming them, exit 1.
    let o = Command::new(&exe)
        .env("LD_LIBRARY_PATH", lib_dir())
        .arg(dir.path().join("keylo.toml"))
        .arg(dir.path().join("nope"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    std::fs::write(dir.path().join("scans/999999.bin"), [0u8; 7]).unwrap();
    let o = Command::new(&exe)
        .env("LD_LIBRARY_PATH", lib_dir())
        .arg(dir.path().join("keylo.toml"))
        .arg(dir.path().join("scans"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("999999.bin: size is not a multiple of 16"),
        "{err}"
    );
}
