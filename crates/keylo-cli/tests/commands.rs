//! The commands work end to end on small simulated data.

mod common;

use common::{keylo, keylo_line, small_sim, stderr, stdout};

#[test]
fn run_writes_trajectories_summary_and_config() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 8);
    let out = tmp.path().join("out");
    let o = keylo(
        &[
            "run",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "trajectory.tum",
        "trajectory.kitti",
        "summary.json",
        "config.toml",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let table = stdout(&o);
    assert!(
        table.contains("ATE RMSE (m)") && table.contains("frames"),
        "{table}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["frames"], 8);
    assert!(
        summary["accuracy"]["ate_rmse_m"].as_f64().is_some(),
        "{summary}"
    );
    assert!(summary["peak_rss_mb"].as_f64().unwrap_or(0.0) > 0.0);
    // The resolved config is itself a valid config.
    let o = keylo(
        &["config", "show", out.join("config.toml").to_str().unwrap()],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn realtime_playback_paces_the_frames_and_keeps_the_results() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 4);
    let run = |out: &str, extra: &[&str]| {
        let out = tmp.path().join(out);
        let mut args = vec![
            "run",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let start = std::time::Instant::now();
        let o = keylo(&args, tmp.path());
        assert!(o.status.success(), "{}", stderr(&o));
        (out, start.elapsed(), stdout(&o))
    };
    let (fast, _, _) = run("fast", &[]);
    // Four frames 0.1 s apart at twice the sensor's rate: the last is released 0.15 s after
    // the first.
    let (paced, took, table) = run("paced", &["--realtime", "2"]);
    assert!(took >= std::time::Duration::from_millis(150), "{took:?}");
    assert!(table.contains("frames late at 2x rate"), "{table}");
    let read = |d: &std::path::Path, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    assert_eq!(
        read(&fast, "trajectory.tum"),
        read(&paced, "trajectory.tum")
    );
    let summary: serde_json::Value = serde_json::from_str(&read(&paced, "summary.json")).unwrap();
    assert_eq!(summary["playback_speed"], 2.0);
    assert!(summary["frames_late"].as_u64().is_some(), "{summary}");
    let unpaced: serde_json::Value = serde_json::from_str(&read(&fast, "summary.json")).unwrap();
    assert!(unpaced.get("playback_speed").is_none(), "{unpaced}");
    // A speed that is not above 0 is refused before any work.
    let o = keylo(
        &[
            "run",
            "--data",
            data.to_str().unwrap(),
            "--realtime",
            "0",
            "--out",
            tmp.path().join("zero").to_str().unwrap(),
        ],
        tmp.path(),
    );
    common::expect_failure(&o, 2, "--realtime");
}

#[test]
fn config_show_fills_defaults_with_docs() {
    let tmp = tempfile::tempdir().unwrap();
    let o = keylo_line("config show --set registrar.voxel_size=0.5", tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("voxel_size = 0.5"), "{text}");
    assert!(text.contains("max_points_per_voxel = 20"), "{text}");
    assert!(text.contains("# Points kept per map voxel."), "{text}");
    assert!(
        text.contains("[output]") && text.contains("on_bad_frame = \"stop\""),
        "{text}"
    );
}

#[test]
fn config_kinds_and_docs_list_backends() {
    let tmp = tempfile::tempdir().unwrap();
    let o = keylo_line("config kinds", tmp.path());
    assert!(stdout(&o).contains("kiss-icp") && stdout(&o).contains("passthrough"));
    let o = keylo_line("config docs", tmp.path());
    assert!(
        stdout(&o).contains("| `max_points_per_voxel` | `20` |"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn kitti_bin_export_writes_bins_and_index_stamped_gt() {
    let tmp = tempfile::tempdir().unwrap();
    let o = keylo_line(
        "sim --frames 3 --format kitti-bin --out bins --set sensor=os1-64 -q",
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let bins = tmp.path().join("bins/velodyne");
    assert_eq!(std::fs::read_dir(&bins).unwrap().count(), 3);
    let pts = keylo::io::kitti_bin::read_kitti_bin(&bins.join("000000.bin")).unwrap();
    assert!(pts.len() > 1000);
    let gt = std::fs::read_to_string(tmp.path().join("bins/gt.tum")).unwrap();
    let stamps: Vec<f64> = gt
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(stamps, vec![0.0, 1.0, 2.0]);
}

#[test]
fn docs_config_md_is_up_to_date() {
    let tmp = tempfile::tempdir().unwrap();
    let o = keylo_line("config docs", tmp.path());
    let committed =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/config.md"))
            .unwrap();
    assert!(
        stdout(&o) == committed,
        "docs/config.md is stale: regenerate it with `keylo config docs > docs/config.md`"
    );
}

#[test]
fn eval_reports_rpe_over_a_distance() {
    let tmp = tempfile::tempdir().unwrap();
    // A curved path (Umeyama alignment, like evo's, needs non-collinear positions).
    let row = |i: usize, scale: f64| {
        let t = i as f64 * 0.2;
        format!(
            "{i} {} {} {} 0 0 0 1\n",
            scale * t * 2.0,
            t.sin(),
            0.1 * t.cos()
        )
    };
    let gt: String = (0..50).map(|i| row(i, 1.0)).collect();
    let est: String = (0..50).map(|i| row(i, 1.02)).collect();
    std::fs::write(tmp.path().join("gt.tum"), gt).unwrap();
    std::fs::write(tmp.path().join("est.tum"), est).unwrap();
    let o = keylo_line(
        "eval --est est.tum --gt gt.tum --delta 10 --delta-unit m",
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("RPE trans RMSE over 10 m"), "{text}");
    let o = keylo_line("eval --est est.tum --gt gt.tum --delta 1.5", tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("whole number"), "{}", stderr(&o));
}
