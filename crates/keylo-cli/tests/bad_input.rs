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

#[test]
fn empty_and_all_nan_frames_stop_the_run_and_keep_the_trajectory() {
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
        "-q",
    ];
    let o = keylo(&args, tmp.path());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("frame 3"), "{}", stderr(&o));
    let tum = std::fs::read_to_string(out.join("trajectory.tum")).unwrap();
    assert_eq!(tum.lines().filter(|l| !l.starts_with('#')).count(), 3);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"failed\"") && summary.contains("no valid finite point"),
        "{summary}"
    );
    no_panic(&o);

    let mut skip = args.to_vec();
    skip.extend(["--set", "output.on_bad_frame=skip"]);
    let o = keylo(&skip, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let tum = std::fs::read_to_string(out.join("trajectory.tum")).unwrap();
    assert_eq!(tum.lines().filter(|l| !l.starts_with('#')).count(), 4);
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
    let o = keylo(
        &[
            "run",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "-q",
        ],
        tmp.path(),
    );
    expect_failure(&o, 3, "000002.klf");
    expect_failure(&o, 3, "truncated");
    let tum = std::fs::read_to_string(out.join("trajectory.tum")).unwrap();
    assert_eq!(tum.lines().filter(|l| !l.starts_with('#')).count(), 2);
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
