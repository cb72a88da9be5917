//! `tests/embed.c`, compiled with `cc` against `include/keylo.h` and `libkeylo_capi.so`, runs a
//! pipeline on five simulated frames, pushed as organised frames and as point clouds with
//! per-point times, and its poses follow the simulator's ground truth.

mod common;

use std::io::Write;
use std::path::Path;
use std::process::Command;

use common::{here, lib_dir};
use keylo::{LidarFrame, Trajectory};

const FRAMES: usize = 5;

fn write_frame(path: &Path, f: &LidarFrame) {
    let mut out = Vec::new();
    out.extend((f.rows as u32).to_le_bytes());
    out.extend((f.cols as u32).to_le_bytes());
    out.extend(f.timestamp.to_le_bytes());
    f.column_times
        .iter()
        .for_each(|t| out.extend(t.to_le_bytes()));
    for p in &f.points {
        p.coords.iter().for_each(|v| out.extend(v.to_le_bytes()));
    }
    f.signal.iter().for_each(|v| out.extend(v.to_le_bytes()));
    out.extend(f.valid.iter().map(|&v| u8::from(v)));
    std::fs::File::create(path)
        .unwrap()
        .write_all(&out)
        .unwrap();
}

/// Five simulated OS1-64 frames (512 columns) written for the C program; their ground truth.
fn simulate(dir: &Path) -> Trajectory {
    common::simulate_lab(FRAMES, &[], |k, frame| {
        write_frame(&dir.join(format!("frame_{k}.bin")), &frame)
    })
}

/// Runs the program; the translation of every frame.
fn run(exe: &Path, config: &str, dir: &Path, mode: &str) -> Vec<[f64; 3]> {
    let cfg = dir.join(format!("{mode}.toml"));
    std::fs::write(&cfg, config).unwrap();
    // Cargo's LD_LIBRARY_PATH names target/debug first, where an older `cargo build` may have
    // left a stale libkeylo_capi.so; the one built with this test is in `lib_dir()`.
    let o = Command::new(exe)
        .env("LD_LIBRARY_PATH", lib_dir())
        .arg(&cfg)
        .arg(dir)
        .arg(FRAMES.to_string())
        .arg(mode)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        text.starts_with(&format!("keylo {}", env!("CARGO_PKG_VERSION"))),
        "{text}"
    );
    assert!(
        text.contains("error points: xyz is NULL or n is 0"),
        "{text}"
    );
    assert!(
        text.contains("map error settings: map.voxel_size = -1: expected a finite value above 0"),
        "{text}"
    );
    let map = keylo::map::Map::open(&dir.join(format!("map_{mode}"))).unwrap();
    assert_eq!(map.manifest().frames, FRAMES);
    assert!(map.manifest().points > 1000 && !map.keyframes().is_empty());
    check_degeneracy(&text);
    assert!(
        text.lines()
            .filter(|l| l.starts_with("covariance "))
            .count()
            >= FRAMES - 1,
        "{text}"
    );
    text.lines()
        .filter_map(|l| l.strip_prefix("pose "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            assert!(v[8] > 1000.0, "registered cloud of {} points", v[8]);
            [v[1], v[2], v[3]]
        })
        .collect()
}

/// `keylo_pipeline_degeneracy`: none for the first frame (nothing to register against), an
/// analysis for every later one; the simulated lab constrains every direction.
fn check_degeneracy(text: &str) {
    let lines: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("degeneracy "))
        .collect();
    assert_eq!(lines.len(), FRAMES, "{text}");
    assert_eq!(lines[0], "0 none");
    for l in &lines[1..] {
        let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
        let (weak, condition, low, high, unit, residuals) = (v[1], v[2], v[3], v[4], v[5], v[6]);
        assert_eq!(weak, 0.0, "{l}");
        assert!(low > 0.0 && high >= low && condition.is_finite(), "{l}");
        assert!((unit - 1.0).abs() < 1e-5, "{l}");
        assert!(residuals > 20.0, "{l}");
    }
}

fn check_against_truth(est: &[[f64; 3]], gt: &Trajectory, mode: &str) {
    assert_eq!(est.len(), FRAMES, "{mode}");
    let truth = (gt.poses[0].inverse() * gt.poses[FRAMES - 1])
        .translation
        .vector;
    let last = nalgebra::Vector3::from(est[FRAMES - 1]);
    assert!(truth.norm() > 0.01, "the simulated sensor moves");
    assert!(
        (last - truth).norm() < 0.15,
        "{mode}: estimated {last:?}, true {truth:?}"
    );
}

#[test]
fn c_program_runs_a_pipeline_on_frames_and_on_points() {
    let dir = tempfile::tempdir().unwrap();
    let gt = simulate(dir.path());
    let exe = dir.path().join("embed");
    common::compile(&here().join("tests/embed.c"), &exe);
    let frames = run(
        &exe,
        "[registrar]\nkind = \"kiss-icp\"\n",
        dir.path(),
        "frame",
    );
    check_against_truth(&frames, &gt, "organised frames");
    let points = run(
        &exe,
        "[source.projection]\nrows = 64\ncols = 512\nfov_up_deg = 22.5\nfov_down_deg = -22.5\n\n\
         [registrar]\nkind = \"kiss-icp\"\n",
        dir.path(),
        "points",
    );
    check_against_truth(&points, &gt, "point clouds");
}

#[test]
fn a_bad_config_is_an_error_message_not_a_crash() {
    let text = std::ffi::CString::new("[registrar]\nkind = \"nope\"\n").unwrap();
    let mut buf = vec![0 as std::ffi::c_char; 512];
    // SAFETY: valid strings and a writable buffer of the given length.
    let p = unsafe {
        keylo_capi::ffi::keylo_pipeline_new(
            text.as_ptr(),
            std::ptr::null(),
            buf.as_mut_ptr(),
            buf.len(),
        )
    };
    assert!(p.is_null());
    // SAFETY: the buffer is NUL-terminated by the call.
    let msg = unsafe { std::ffi::CStr::from_ptr(buf.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    assert!(msg.contains("`registrar.kind = \"nope\"`"), "{msg}");
}
