//! Bad input: a clear error naming the file or key, a non-zero exit, no panic, and the
//! trajectory of the frames done before a failure kept.

mod common;

use common::{expect_failure, keylo, keylo_line, small_sim, stderr};
use keylo::io::frames::codec;

fn no_panic(o: &std::process::Output) {
    let e = stderr(o);
    assert!(!e.contains("panicked"), "panic: {e}");
}

#[test]
fn missing_config_file_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let o = keylo_line("run nope.toml -q", tmp.path());
    expect_failure(&o, 2, "nope.toml");
    no_panic(&o);
}

#[test]
fn unknown_section_key_kind_and_wrong_type_name_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let cases = [
        (
            "[sourse]\nkind = 'sim'\n",
            "unknown section `[sourse]`",
            "allowed sections",
        ),
        (
            "[registrar]\nvoxel_sise = 1.0\n",
            "registrar.voxel_sise",
            "voxel_size",
        ),
        (
            "[registrar]\nkind = 'kiss'\n",
            "registrar.kind = \"kiss\"",
            "kiss-icp",
        ),
        (
            "[registrar]\nmax_range = 'far'\n",
            "registrar.max_range",
            "f64",
        ),
        (
            "[source]\nkind = 'sim'\nframes = -3\n",
            "source.frames",
            "usize",
        ),
        ("[output]\ntum = 1\n", "output.tum", "bool"),
        (
            "[detector]\nkind = 'none'\nthreshold = 3\n",
            "detector.threshold",
            "no parameters",
        ),
    ];
    for (i, (text, key, allowed)) in cases.iter().enumerate() {
        let file = tmp.path().join(format!("c{i}.toml"));
        std::fs::write(&file, text).unwrap();
        let o = keylo(&["config", "show", file.to_str().unwrap()], tmp.path());
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{text}: {e}");
        assert!(
            e.contains(&format!("c{i}.toml")),
            "{text}: file not named: {e}"
        );
        assert!(e.contains(key), "{text}: key not named: {e}");
        assert!(
            e.contains(allowed),
            "{text}: expected/allowed not named: {e}"
        );
        no_panic(&o);
    }
}

#[test]
fn bad_parameter_values_are_rejected_at_build_time() {
    let tmp = tempfile::tempdir().unwrap();
    let o = keylo_line(
        "run --set registrar.max_range=-1 --set source.frames=2 -q",
        tmp.path(),
    );
    expect_failure(&o, 2, "max_range");
    no_panic(&o);
}

#[test]
fn data_paths_that_hold_no_frames_are_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let o = keylo_line("run --data missing-dir -q", tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing-dir"));
    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let o = keylo(
        &["run", "--data", empty.to_str().unwrap(), "-q"],
        tmp.path(),
    );
    expect_failure(&o, 2, "no source recognises");
    // A manifest that promises frames the folder does not hold.
    small_sim(&empty, 2);
    std::fs::remove_file(empty.join("frames/000001.klf")).unwrap();
    let o = keylo(
        &["run", "--data", empty.to_str().unwrap(), "-q"],
        tmp.path(),
    );
    expect_failure(&o, 2, "keylo-frames.json");
    no_panic(&o);
}

/// Replaces frame `i` of a folder with `edit(frame)`.
fn edit_frame(dir: &std::path::Path, i: usize, edit: impl FnOnce(&mut keylo::LidarFrame)) {
    let path = dir.join(format!("frames/{i:06}.klf"));
    let bytes = std::fs::read(&path).unwrap();
    let beams = std::sync::Arc::new(
        keylo::io::frames::Manifest::read(&dir.join("keylo-frames.json"))
            .unwrap()
            .beams,
    );
    let mut frame = codec::decode(&path, &bytes, &beams).unwrap();
    edit(&mut frame);
    std::fs::write(&path, codec::encode(&frame)).unwrap();
}

fn pose_lines(out: &std::path::Path) -> usize {
    let tum = std::fs::read_to_string(out.join("trajectory.tum")).unwrap();
    tum.lines().filter(|l| !l.starts_with('#')).count()
}

#[test]
fn empty_and_all_nan_frames_are_predicted_or_stop_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 6);
    edit_frame(&data, 3, |f| f.valid.iter_mut().for_each(|v| *v = false));
    edit_frame(&data, 4, |f| {
        f.points.iter_mut().for_each(|p| p.x = f32::NAN)
    });
    let out = tmp.path().join("out");
    let args = [
        "run",
        "--data",
        data.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    // Default (`registrar.empty_frame = "predict"`, upstream KISS-ICP's behaviour): the two
    // frames get the constant-velocity prediction, each with a warning naming it degenerate,
    // and are counted.
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    for frame in ["frame 3", "frame 4"] {
        assert!(stderr(&o).contains(frame), "{}", stderr(&o));
    }
    assert!(
        stderr(&o).contains("is degenerate: 0 registered points"),
        "{}",
        stderr(&o)
    );
    assert!(
        stderr(&o).contains("motion model's prediction"),
        "{}",
        stderr(&o)
    );
    assert_eq!(pose_lines(&out), 6);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"frames_predicted\": 2"), "{summary}");
    no_panic(&o);

    // `empty_frame = "error"`: the run stops at frame 3 and keeps the frames before it.
    let mut stop = args.to_vec();
    stop.extend(["-q", "--set", "registrar.empty_frame=error"]);
    let o = keylo(&stop, tmp.path());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("frame 3"), "{}", stderr(&o));
    assert_eq!(pose_lines(&out), 3);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"failed\"") && summary.contains("no valid finite point"),
        "{summary}"
    );
    no_panic(&o);

    let mut skip = stop.clone();
    skip.extend(["--set", "output.on_bad_frame=skip"]);
    let o = keylo(&skip, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(pose_lines(&out), 4);
}

/// KITTI-style scans (`keylo sim --format kitti-bin`) with scan 2 replaced by `bytes`.
fn kitti_with_scan_2(dir: &std::path::Path, bytes: &[u8]) -> std::path::PathBuf {
    let data = dir.join("bin");
    let o = keylo_line(
        &format!(
            "sim -q --scene lab --frames 5 --format kitti-bin --out {} \
             --set sensor=os1-64 --set columns=512",
            data.display()
        ),
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let velodyne = data.join("velodyne");
    let scan = std::fs::read_dir(&velodyne)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bin"))
        .min_by_key(|p| p.file_name().map(|n| n.to_os_string()))
        .unwrap();
    let third = scan.with_file_name(format!("{:06}.bin", 2));
    assert!(third.is_file(), "{}", third.display());
    std::fs::write(&third, bytes).unwrap();
    velodyne
}

#[test]
fn bad_kitti_scans_name_the_file_and_frame() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let run = |data: &std::path::Path, extra: &[&str]| {
        let mut args = vec![
            "run",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        keylo(&args, tmp.path())
    };
    // All-zero and NaN/inf points: nothing to register, so the scan is predicted (warned,
    // naming the file) or, with `empty_frame = "error"`, stops the run naming file and frame.
    let mut rows: Vec<u8> = Vec::new();
    for v in [
        [0.0f32; 4],
        [f32::NAN, 1.0, 1.0, 0.0],
        [f32::INFINITY, 0.0, 0.0, 0.0],
    ] {
        rows.extend(v.iter().flat_map(|x| x.to_le_bytes()));
    }
    for (case, bytes) in [("zeros and nan", rows), ("empty", Vec::new())] {
        let dir = tempfile::tempdir().unwrap();
        let data = kitti_with_scan_2(dir.path(), &bytes);
        let o = run(&data, &[]);
        assert!(o.status.success(), "{case}: {}", stderr(&o));
        assert!(stderr(&o).contains("frame 2 ("), "{case}: {}", stderr(&o));
        assert!(stderr(&o).contains("000002.bin"), "{case}: {}", stderr(&o));
        assert_eq!(pose_lines(&out), 5, "{case}");
        let o = run(&data, &["-q", "--set", "registrar.empty_frame=error"]);
        expect_failure(&o, 3, "frame 2");
        expect_failure(&o, 3, "000002.bin");
        assert_eq!(pose_lines(&out), 2, "{case}");
    }
    // A file whose size is not a multiple of 16 bytes: the run stops there.
    let dir = tempfile::tempdir().unwrap();
    let data = kitti_with_scan_2(dir.path(), &[0u8; 18]);
    let o = run(&data, &["-q"]);
    expect_failure(&o, 3, "000002.bin");
    expect_failure(&o, 3, "not a multiple of 16");
    assert_eq!(pose_lines(&out), 2);
}

#[test]
fn a_truncated_frame_file_is_named_and_earlier_frames_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 4);
    let bad = data.join("frames/000002.klf");
    let bytes = std::fs::read(&bad).unwrap();
    std::fs::write(&bad, &bytes[..bytes.len() / 2]).unwrap();
    let out = tmp.path().join("out");
    let o = run_quiet(&data, &out, tmp.path());
    expect_failure(&o, 3, "000002.klf");
    expect_failure(&o, 3, "truncated");
    assert_eq!(pose_lines(&out), 2);
}

/// `keylo run -q --data DATA --out OUT`.
fn run_quiet(
    data: &std::path::Path,
    out: &std::path::Path,
    cwd: &std::path::Path,
) -> std::process::Output {
    let (data, out) = (data.to_str().unwrap(), out.to_str().unwrap());
    keylo(&["run", "--data", data, "--out", out, "-q"], cwd)
}

#[test]
fn bad_trajectory_files_are_named_by_eval() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("a.tum"), "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0\n").unwrap();
    std::fs::write(tmp.path().join("b.tum"), "0 0 0 0 0 0 0 1\n").unwrap();
    let o = keylo_line("eval --est a.tum --gt b.tum", tmp.path());
    expect_failure(&o, 2, "a.tum");
    no_panic(&o);
}

/// Regressions from the review of the first release.
#[test]
fn huge_thresholds_and_thread_counts_are_rejected_up_front() {
    let tmp = tempfile::tempdir().unwrap();
    for set in [
        "registrar.max_range=1e200",
        "registrar.initial_threshold=1e200",
        "registrar.max_num_threads=100000",
    ] {
        let o = keylo_line(
            &format!("run -q --set source.frames=2 --set {set}"),
            tmp.path(),
        );
        assert_eq!(o.status.code(), Some(2), "{set}: {}", stderr(&o));
        no_panic(&o);
    }
    let o = keylo_line("run -q --threads 100000", tmp.path());
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn ground_truth_and_data_problems_are_found_before_running() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 6);
    let d = data.to_str().unwrap();
    let o = keylo_line(
        &format!("run -q --data {d} --gt /nonexistent.tum"),
        tmp.path(),
    );
    expect_failure(&o, 2, "/nonexistent.tum");
    let o = keylo_line(
        &format!("run -q --data {d} --set source.start=50"),
        tmp.path(),
    );
    expect_failure(&o, 2, "source.start");
    let o = keylo_line(
        &format!("run -q --data {d} --set source.kind=sim"),
        tmp.path(),
    );
    expect_failure(&o, 2, "conflicts with --data");
    // Re-simulating into the same folder with fewer frames leaves a consistent folder.
    small_sim(&data, 3);
    let o = keylo_line(&format!("run -q --data {d} --out {d}/run"), tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    // A KITTI estimate (no stamps) pairs one for one with an equally long TUM reference only.
    let o = keylo_line(
        &format!("eval --est {d}/run/trajectory.kitti --gt {d}/gt.tum"),
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    small_sim(&data, 5);
    let o = keylo_line(
        &format!("eval --est {d}/run/trajectory.kitti --gt {d}/gt.tum"),
        tmp.path(),
    );
    expect_failure(&o, 2, "no time stamps");
}

#[test]
fn a_pcd_with_fewer_points_than_its_header_says_stops_at_its_frame() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("pcd");
    std::fs::create_dir_all(&data).unwrap();
    let header = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n\
                  COUNT 1 1 1\nWIDTH 5\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 5\nDATA ascii\n";
    let rows = ["4 5 6", "7 -8 9", "-10 1 1", "5 5 1", "-3 -4 2"];
    for i in 0..3 {
        let n = if i == 1 { 3 } else { 5 };
        let body: String = rows[..n].iter().map(|r| format!("{r}\n")).collect();
        std::fs::write(data.join(format!("{i}.pcd")), format!("{header}{body}")).unwrap();
    }
    let out = tmp.path().join("out");
    let o = run_quiet(&data, &out, tmp.path());
    expect_failure(&o, 3, "frame 1");
    expect_failure(&o, 3, "1.pcd");
    expect_failure(&o, 3, "of the 5 in POINTS");
    assert_eq!(pose_lines(&out), 1);
}
