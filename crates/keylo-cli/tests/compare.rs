//! `keylo compare`: grid expansion, tables from real runs, failed runs as rows, resume, and
//! bad grid keys.

mod common;

use std::path::{Path, PathBuf};

use common::{config, keylo, small_sim, stderr, stdout};

fn read_json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// Splits one CSV line (quoted fields may hold commas and doubled quotes).
fn csv_fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            _ => out.last_mut().unwrap().push(c),
        }
    }
    out
}

#[test]
fn grid_expands_to_every_combination_and_skips_axes_a_config_lacks() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 2);
    let (raw, akaze) = (
        config("paper/raw-kiss-icp.toml"),
        config("paper/indoor-akaze-kiss-icp.toml"),
    );
    let o = keylo(
        &[
            "compare",
            &raw,
            &akaze,
            "--data",
            data.to_str().unwrap(),
            "--grid",
            "k_sig=4,5,7",
            "--grid",
            "downsampler.windows.range=4,7",
            "--dry-run",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let lines: Vec<String> = stdout(&o).lines().map(str::to_string).collect();
    // The raw-cloud config has no window sizes: it runs once; the keypoint one 3 × 2 times.
    assert_eq!(lines.len(), 7, "{lines:?}");
    assert_eq!(lines[0].trim(), "seq/raw-kiss-icp");
    for (i, (s, r)) in [(4, 4), (4, 7), (5, 4), (5, 7), (7, 4), (7, 7)]
        .iter()
        .enumerate()
    {
        let want = format!(
            "seq/indoor-akaze-kiss-icp_{s}_{r}\tdownsampler.windows={{ \"range\" = {r}, \"signal\" = {s} }}"
        );
        assert_eq!(lines[i + 1], want);
    }
    assert!(
        stderr(&o).contains("runs once without it"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bad_grid_keys_are_named() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 2);
    let d = data.to_str().unwrap();
    let o = keylo(
        &[
            "compare",
            "--data",
            d,
            "--grid",
            "registrar.voxel_sise=0.5,1",
        ],
        tmp.path(),
    );
    common::expect_failure(&o, 2, "--grid registrar.voxel_sise");
    assert!(
        stderr(&o).contains("unknown field `voxel_sise`"),
        "{}",
        stderr(&o)
    );
    let o = keylo(
        &[
            "compare",
            "--data",
            d,
            "--grid",
            "registrar.kind=no-such-icp",
        ],
        tmp.path(),
    );
    common::expect_failure(&o, 2, "--grid registrar.kind");
    let o = keylo(&["compare", "--data", d, "--grid", "k_sig"], tmp.path());
    common::expect_failure(&o, 2, "--grid k_sig: expected KEY=V1,V2");
}

#[test]
fn compare_fills_every_column_csv_and_json_agree_and_resume_skips() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 12);
    let out = tmp.path().join("cmp");
    let args = [
        "compare".to_string(),
        config("paper/raw-kiss-icp.toml"),
        config("examples/corridor-voxel-kiss-icp.toml"),
        "--data".into(),
        data.display().to_string(),
        "--out".into(),
        out.display().to_string(),
        "--jobs".into(),
        "2".into(),
    ];
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let json = read_json(&out.join("compare.json"));
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    let csv = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    let mut lines = csv.lines();
    let header = csv_fields(lines.next().unwrap());
    let rows: Vec<Vec<String>> = lines.map(csv_fields).collect();
    assert_eq!(rows.len(), 2);
    for (row, run) in rows.iter().zip(runs) {
        assert_eq!(run["verdict"], "ok", "{run}");
        assert_eq!(row.len(), header.len());
        for (name, value) in header.iter().zip(row) {
            if name == "frames_late" {
                // Only a `--realtime` run counts late frames.
                assert!(value.is_empty() && run[name.as_str()].is_null(), "{run}");
                continue;
            }
            assert!(!value.is_empty(), "column {name} is empty: {row:?}");
            match &run[name.as_str()] {
                serde_json::Value::Number(n) => {
                    let (a, b) = (n.as_f64().unwrap(), value.parse::<f64>().unwrap());
                    assert!(
                        (a - b).abs() <= 1e-9 * a.abs().max(1.0),
                        "{name}: {a} vs {b}"
                    );
                }
                serde_json::Value::String(s) => assert_eq!(s, value, "{name}"),
                serde_json::Value::Bool(b) => assert_eq!(b.to_string(), *value, "{name}"),
                other => panic!("{name}: unexpected JSON value {other}"),
            }
        }
        assert!(
            run["frames"] == 12 && run["peak_rss_mb"].as_f64().unwrap() > 0.0,
            "{run}"
        );
        assert!(run["odometry_hz"].as_f64().unwrap() > 0.0, "{run}");
    }
    // Raw cloud vs voxel grid: the voxel grid hands fewer points to the registrar.
    assert!(runs[1]["mean_points"].as_f64() < runs[0]["mean_points"].as_f64());
    assert_eq!(runs[0]["rate_vs_raw"].as_f64(), Some(1.0));
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(
        md.contains("Divergence criterion") && md.contains("| Avg Pts |"),
        "{md}"
    );
    for f in ["trajectories", "ape", "points", "rate", "rss"] {
        for ext in ["png", "svg"] {
            let p = out.join("plots/seq").join(format!("{f}.{ext}"));
            assert!(
                std::fs::metadata(&p)
                    .map(|m| m.len() > 1000)
                    .unwrap_or(false),
                "{p:?}"
            );
        }
    }

    // Resume: both runs are found finished and not run again.
    let summary: PathBuf = out.join("runs/seq/raw-kiss-icp/summary.json");
    let before = std::fs::metadata(&summary).unwrap().modified().unwrap();
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stderr(&o).matches("skipped: summary.json").count(),
        2,
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::metadata(&summary).unwrap().modified().unwrap(),
        before
    );
    let again = read_json(&out.join("compare.json"));
    assert!(again["runs"]
        .as_array()
        .unwrap()
        .iter()
        .all(|r| r["resumed"] == true));
    assert_eq!(again["runs"][0]["trans_rmse_m"], runs[0]["trans_rmse_m"]);

    // Other settings in the same folders: the finished runs are not reused.
    let mut changed = args.clone();
    changed.extend(["--set", "registrar.max_range=20"]);
    let o = keylo(&changed, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stderr(&o).matches("finished run of other settings").count(),
        2,
        "{}",
        stderr(&o)
    );
    let third = read_json(&out.join("compare.json"));
    assert!(third["runs"]
        .as_array()
        .unwrap()
        .iter()
        .all(|r| r["resumed"] == false));
}

#[test]
fn a_failing_run_is_a_row_and_the_others_go_on() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 6);
    let out = tmp.path().join("cmp");
    let o = keylo(
        &[
            "compare",
            &config("paper/indoor-akaze-kiss-icp.toml"),
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--set",
            "downsampler.on_too_few=all-points",
            "--grid",
            "downsampler.min_points=1,100000000",
            "--grid",
            "downsampler.on_too_few=all-points,error",
            "--no-plots",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let json = read_json(&out.join("compare.json"));
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 4, "{json}");
    // Only "fewer than 10⁸ points is an error" stops; it stops on its first frame.
    let failed: Vec<_> = runs.iter().filter(|r| r["verdict"] == "failed").collect();
    assert_eq!(failed.len(), 1, "{json}");
    let f = failed[0];
    assert!(
        f["variant"]
            .as_str()
            .unwrap()
            .contains("min_points=100000000"),
        "{f}"
    );
    assert!(
        f["variant"].as_str().unwrap().contains("on_too_few=error"),
        "{f}"
    );
    assert!(
        f["reason"].as_str().unwrap().contains("too few points"),
        "{f}"
    );
    assert!(runs
        .iter()
        .filter(|r| r["verdict"] == "ok")
        .all(|r| r["frames"] == 6));
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(md.contains("N/A (failed)"), "{md}");
    assert!(
        stderr(&o).contains("failed (exit status 3)"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_kitti_ground_truth_is_paired_one_for_one_with_the_estimate() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 8);
    // The simulator's gt.tum as a KITTI file (3×4 matrices, no stamps).
    let tum = std::fs::read_to_string(data.join("gt.tum")).unwrap();
    let mut kitti = String::new();
    for line in tum
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            v[7], v[4], v[5], v[6],
        ));
        let r = q.to_rotation_matrix();
        let m = r.matrix();
        kitti += &format!(
            "{} {} {} {} {} {} {} {} {} {} {} {}\n",
            m[(0, 0)],
            m[(0, 1)],
            m[(0, 2)],
            v[1],
            m[(1, 0)],
            m[(1, 1)],
            m[(1, 2)],
            v[2],
            m[(2, 0)],
            m[(2, 1)],
            m[(2, 2)],
            v[3]
        );
    }
    let gt = tmp.path().join("gt_kitti.txt");
    std::fs::write(&gt, kitti).unwrap();
    let out = tmp.path().join("cmp");
    let raw = config("paper/raw-kiss-icp.toml");
    let args = [
        "compare",
        &raw,
        "--data",
        data.to_str().unwrap(),
        "--gt",
        gt.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--no-plots",
    ];
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let json = read_json(&out.join("compare.json"));
    let run = &json["runs"][0];
    let t = run["trans_rmse_m"].as_f64().unwrap_or(f64::NAN);
    assert!(t.is_finite() && t < 0.5, "{run}");
}

#[test]
fn a_run_past_the_timeout_is_stopped_its_frames_kept_and_rerun_on_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 40);
    let out = tmp.path().join("cmp");
    let out_s = out.to_str().unwrap().to_string();
    let cfg = config("paper/raw-kiss-icp.toml");
    // max_frames=1 ends well within the limit; 40 frames with a 2 cm voxel map take about 7 s
    // (release build).
    let args = [
        "compare",
        &cfg,
        "--data",
        data.to_str().unwrap(),
        "--out",
        &out_s,
        "--set",
        "registrar.voxel_size=0.02",
        "--grid",
        "source.max_frames=1,40",
        "--timeout",
        "2",
        "--no-plots",
    ];
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let json = read_json(&out.join("compare.json"));
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2, "{json}");
    let quick = &runs[0];
    assert_eq!(quick["verdict"], "ok", "{quick}");
    assert_eq!(quick["frames"], 1, "{quick}");
    let slow = &runs[1];
    assert_eq!(slow["verdict"], "failed", "{slow}");
    let reason = slow["reason"].as_str().unwrap();
    assert!(reason.starts_with("timed out after"), "{reason}");
    // SIGTERM lets the run write what it has: its summary and trajectory are there.
    assert!(reason.contains("stopped;"), "{reason}");
    let frames = slow["frames"].as_u64().unwrap();
    assert!(frames < 40, "{slow}");
    let slow_dir = out.join("runs/seq/source.max_frames=40");
    let tum = std::fs::read_to_string(slow_dir.join("trajectory.tum")).unwrap();
    assert_eq!(tum.lines().count() as u64, frames, "{tum}");
    assert!(stderr(&o).contains("timed out after"), "{}", stderr(&o));
    // Resume: the finished run is skipped, the timed-out one is run again.
    let again = keylo(&args, tmp.path());
    assert!(again.status.success(), "{}", stderr(&again));
    let json = read_json(&out.join("compare.json"));
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs[0]["resumed"], true, "{json}");
    assert_eq!(runs[1]["resumed"], false, "{json}");
}

#[test]
fn same_budget_adds_random_and_voxel_baselines_with_the_keypoint_point_count() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("lab");
    small_sim(&data, 5);
    let out = tmp.path().join("cmp");
    let o = keylo(
        &[
            "compare",
            &config("paper/raw-kiss-icp.toml"),
            &config("paper/indoor-akaze-kiss-icp.toml"),
            "--data",
            data.to_str().unwrap(),
            "--same-budget",
            "--out",
            out.to_str().unwrap(),
            "--no-plots",
            "-q",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let json = read_json(&out.join("compare.json"));
    let rows = json["runs"].as_array().unwrap();
    let find = |variant: &str| {
        rows.iter()
            .find(|r| r["variant"] == variant)
            .unwrap_or_else(|| panic!("no row {variant}: {json}"))
    };
    // The raw config has no keypoint windows: it runs once, without baselines.
    assert_eq!(rows.len(), 4, "{json}");
    let _ = find("raw-kiss-icp");
    let keypoints = find("indoor-akaze-kiss-icp");
    let random = find("indoor-akaze-kiss-icp +random");
    let voxel = find("indoor-akaze-kiss-icp +voxel-budget");
    assert_eq!(random["downsampler"], "random");
    assert_eq!(voxel["downsampler"], "voxel-budget");
    let points = |r: &serde_json::Value| r["mean_points"].as_f64().unwrap();
    assert!(points(keypoints) > 0.0);
    // `random` keeps exactly the windows' count each frame; `voxel-budget` at most that many.
    assert_eq!(points(random), points(keypoints));
    assert!(points(voxel) <= points(keypoints) && points(voxel) > 0.8 * points(keypoints));
    // Every pose is stamped at its frame's end, whichever points were registered: the four
    // runs' trajectories have the raw run's stamps, so each pairs with the reference alike.
    let stamps = |variant: &str| -> Vec<String> {
        let tum = out.join("runs/lab").join(variant).join("trajectory.tum");
        let text = std::fs::read_to_string(&tum).unwrap_or_else(|e| panic!("{tum:?}: {e}"));
        text.lines()
            .map(|l| l.split_whitespace().next().unwrap_or("").to_string())
            .collect()
    };
    let raw = stamps("raw-kiss-icp");
    assert_eq!(raw.len(), 5);
    for v in [
        "indoor-akaze-kiss-icp",
        "indoor-akaze-kiss-icp__random",
        "indoor-akaze-kiss-icp__voxel-budget",
    ] {
        assert_eq!(stamps(v), raw, "{v}");
    }
}

#[test]
fn realtime_paces_every_run_and_says_so_and_bad_speeds_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 4);
    let out = tmp.path().join("cmp");
    let cfg = config("paper/raw-kiss-icp.toml");
    let args = |speed: &str| {
        vec![
            "compare".to_string(),
            cfg.clone(),
            "--data".into(),
            data.display().to_string(),
            "--out".into(),
            out.display().to_string(),
            format!("--realtime={speed}"),
            "--no-plots".into(),
        ]
    };
    let run = |a: &[String]| {
        keylo(
            &a.iter().map(String::as_str).collect::<Vec<_>>(),
            tmp.path(),
        )
    };
    let o = run(&args("20"));
    assert!(o.status.success(), "{}", stderr(&o));
    let dir = out.join("runs/seq/raw-kiss-icp");
    let summary = read_json(&dir.join("summary.json"));
    assert_eq!(summary["playback_speed"], 20.0, "{summary}");
    let row = &read_json(&out.join("compare.json"))["runs"][0];
    assert!(row["frames_late"].is_u64(), "{row}");
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(md.contains("Played back at 20×"), "{md}");
    let plan = std::fs::read_to_string(dir.join("compare-plan.json")).unwrap();
    assert!(plan.contains("\"realtime\": 20"), "{plan}");
    // Another speed is another plan: the run is done again, not resumed.
    let o = run(&args("40"));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        read_json(&out.join("compare.json"))["runs"][0]["resumed"],
        false
    );
    for bad in ["0", "-1", "inf"] {
        let o = run(&args(bad));
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        assert!(stderr(&o).contains("--realtime"), "{bad}: {}", stderr(&o));
    }
}
