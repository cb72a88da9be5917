//! `keylo sim realism`: simulated images against real ones — the tables, the histograms and
//! bad input.

mod common;

use std::path::{Path, PathBuf};

use common::{expect_failure, keylo, stdout};

fn real_images() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/kpeval/images/os0")
}

#[test]
fn realism_writes_the_tables_and_histograms() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("realism");
    let (real, out_s) = (real_images(), out.to_str().unwrap().to_string());
    let o = keylo(
        &[
            "sim",
            "realism",
            "--real",
            real.to_str().unwrap(),
            "--frames",
            "3",
            "--seeds",
            "2",
            "--set",
            "sensor=os1-64",
            "--set",
            "columns=512",
            "--channels",
            "signal,range",
            "--combos",
            "ORB_ORB,FAST_BRISK",
            "--jobs",
            "1",
            "--out",
            &out_s,
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let md = std::fs::read_to_string(out.join("realism.md")).unwrap();
    assert_eq!(md, stdout(&o).split("\nresults in").next().unwrap());
    for needle in [
        "keypoint count inside the real interquartile range: **",
        "| ORB_ORB |",
        "| FAST_BRISK | match_ratio |",
        "| sim signal | ",
        "| sim signal-stretched | ",
        "| sim range | ",
        "## Row profile",
        "| difference | row residual | column residual |",
    ] {
        assert!(md.contains(needle), "realism.md lacks `{needle}`:\n{md}");
    }
    // Every set has both combinations' keypoint counts.
    let csv = std::fs::read_to_string(out.join("realism.csv")).unwrap();
    for set in ["real", "sim signal", "sim signal-stretched", "sim range"] {
        for combo in ["ORB_ORB", "FAST_BRISK"] {
            let row = format!("{set},{combo},keypoints,");
            assert!(csv.contains(&row), "realism.csv lacks {row}");
        }
    }
    // Histograms: one column per set, each summing to 1 per histogram.
    let hist = std::fs::read_to_string(out.join("histograms.csv")).unwrap();
    let mut lines = hist.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.len(), 2 + 4, "{header:?}");
    let mut sums = std::collections::HashMap::<&str, Vec<f64>>::new();
    for l in lines {
        let cells: Vec<&str> = l.split(',').collect();
        let s = sums.entry(cells[0]).or_insert_with(|| vec![0.0; 4]);
        for (k, v) in cells[2..].iter().enumerate() {
            s[k] += v.parse::<f64>().unwrap();
        }
    }
    for kind in ["intensity", "gradient"] {
        for (k, s) in sums[kind].iter().enumerate() {
            assert!(
                (s - 1.0).abs() < 1e-9,
                "{kind} histogram of set {k} sums to {s}"
            );
        }
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("realism.json")).unwrap()).unwrap();
    let sets = json["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 4);
    assert_eq!(sets[0]["intensity_distance"]["emd"], 0.0);
    assert!(sets[1]["intensity_distance"]["emd"].as_f64().unwrap() > 0.0);
}

#[test]
fn realism_bad_input_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let real = real_images();
    let real = real.to_str().unwrap();
    let cases: [(&[&str], &str); 6] = [
        (&["--real", "no-such-folder"], "--real no-such-folder"),
        (
            &["--real", real, "--channels", "colour"],
            "unknown channel `colour`",
        ),
        (&["--real", real, "--frames", "1"], "--frames 1"),
        (&["--real", real, "--seeds", "0"], "--seeds 0"),
        (&["--real", real, "--jobs", "0"], "--jobs 0"),
        (&["--real", real, "--moving-lap", "1"], "--moving-lap 1"),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["sim", "realism", "--out", "o", "--combos", "ORB_ORB"];
        args.extend_from_slice(extra);
        expect_failure(&keylo(&args, tmp.path()), 2, needle);
    }
}

#[test]
fn still_and_moving_are_reported_side_by_side() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("realism");
    let real = real_images();
    let args = [
        "sim",
        "realism",
        "--real",
        real.to_str().unwrap(),
        "--real-frames",
        "2",
        "--moving-start",
        "0",
        "--frames",
        "3",
        "--seeds",
        "1",
        "--set",
        "sensor=os1-64",
        "--set",
        "columns=512",
        "--channels",
        "signal",
        "--combos",
        "ORB_ORB",
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", common::stderr(&o));
    let md = std::fs::read_to_string(out.join("realism.md")).unwrap();
    for needle in [
        "still and moving",
        "**Still**: real images 0–1",
        "**Moving**: real images 0–1",
        "`speed_scale = ",
        "`sway_scale = ",
        "change beyond it of ",
        "| keypoint count inside the real interquartile range | ",
        "| ORB_ORB | keypoints | ",
        "| ORB_ORB | match_score | ",
    ] {
        assert!(md.contains(needle), "realism.md lacks `{needle}`:\n{md}");
    }
    for half in ["still", "moving"] {
        let full = std::fs::read_to_string(out.join(half).join("realism.md")).unwrap();
        assert!(full.contains(&format!("the {half} half")), "{full}");
    }
    // The motion was matched: the rounds are printed with the real shift.
    assert!(
        common::stderr(&o).contains("motion, round 1"),
        "{}",
        common::stderr(&o)
    );
    // A moving stretch past the folder's end is named.
    let mut bad = args.to_vec();
    let at = bad.iter().position(|a| *a == "0").unwrap();
    bad[at] = "1";
    expect_failure(&keylo(&bad, tmp.path()), 2, "from image 1 on");
}
