//! `keylo keypoints eval` and `sweep`: agreement with an independent OpenCV-Python
//! implementation of the paper's metrics, output files, resume, and bad input.

mod common;

use std::path::{Path, PathBuf};

use common::{expect_failure, keylo, read_csv, small_sim, stderr};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/kpeval")
}

const REFERENCE_COMBOS: &str =
    "AKAZE_AKAZE,ORB_ORB,SIFT_SIFT,BRISK_BRISK,FAST_BRISK,FAST_SIFT,SHITOMASI_SIFT,HARRIS_BRISK";

#[test]
fn every_metric_agrees_with_the_opencv_python_reference() {
    let tmp = tempfile::tempdir().unwrap();
    let reference = read_csv(&fixtures().join("reference.csv"));
    let keys = [
        "keypoints",
        "described",
        "robustness_rotation",
        "robustness_scaling",
        "robustness_scaling_corrected",
        "robustness_blur",
        "matches",
        "match_ratio",
        "inliers",
        "match_score",
        "knn_passed",
        "knn_total",
    ];
    let mut compared = 0;
    for set in ["os0", "sim"] {
        let out = tmp.path().join(set);
        let data = fixtures().join("images").join(set);
        let o = keylo(
            &[
                "keypoints",
                "eval",
                "--data",
                data.to_str().unwrap(),
                "--combos",
                REFERENCE_COMBOS,
                "--out",
                out.to_str().unwrap(),
                "--no-plots",
                "-q",
            ],
            tmp.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let ours = read_csv(&out.join("per_image.csv"));
        for r in reference.iter().filter(|r| r["dataset"] == set) {
            let o = ours
                .iter()
                .find(|o| o["combo"] == r["combo"] && o["index"] == r["index"])
                .unwrap_or_else(|| panic!("no row for {r:?}"));
            for k in keys {
                let (a, b) = (&r[k], &o[k]);
                let same = match (a.is_empty(), b.is_empty()) {
                    (true, true) => true,
                    (false, false) => {
                        (a.parse::<f64>().unwrap() - b.parse::<f64>().unwrap()).abs() < 1e-6
                    }
                    _ => false,
                };
                assert!(
                    same,
                    "{set} {} image {}: {k}: python {a}, keylo {b}",
                    r["combo"], r["index"]
                );
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 56 * 12);
}

#[test]
fn eval_writes_tables_json_and_plots_and_compares_with_the_paper() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 4);
    let paper = tmp.path().join("paper.tsv");
    std::fs::write(
        &paper,
        "figure\tcombination\tq1\tmedian\tq3\n1_Keypoints_number\tSHITOMASI\t500\t564\t600\n\
         4_Match_Ratio\tSHITOMASI_BRIEF\t0.7\t0.768\t0.8\n",
    )
    .unwrap();
    let out = tmp.path().join("ev");
    let o = keylo(
        &[
            "keypoints",
            "eval",
            "--data",
            data.to_str().unwrap(),
            "--combos",
            "SHITOMASI_BRIEF,SHITOMASI_FREAK,FAST_BRISK",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "512",
            "--height",
            "64",
            "--paper",
            paper.to_str().unwrap(),
            "--jobs",
            "2",
            "--images",
            "2",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&out.join("per_image.csv"));
    assert_eq!(rows.len(), 4 * 3);
    // --images 2: each detector on images 0 and 2, as evaluated (512×64, drawn twice as
    // large), with red keypoint dots.
    for name in [
        "SHITOMASI_00000",
        "SHITOMASI_00002",
        "FAST_00000",
        "FAST_00002",
    ] {
        let path = out.join(format!("images/{name}.png"));
        let file = std::fs::File::open(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (1024, 128), "{name}");
        let red = buf[..info.buffer_size()]
            .chunks(3)
            .filter(|p| p == &[255, 40, 40])
            .count();
        assert!(red >= 9, "{name}: no keypoint drawn");
    }
    assert!(!out.join("images/SHITOMASI_00001.png").exists());
    assert!(rows
        .iter()
        .all(|r| r["width"] == "512" && r["height"] == "64"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["combos"].as_array().unwrap().len(), 3, "{json}");
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("(564)") && md.contains("(0.768)"), "{md}");
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(
        summary.contains(",keypoints,") && summary.contains("564"),
        "{summary}"
    );
    for m in [
        "keypoints",
        "robustness_rotation",
        "match_ratio",
        "distinctiveness",
    ] {
        assert!(out.join(format!("plots/{m}.png")).is_file(), "{m}");
        assert!(out.join(format!("plots/{m}.svg")).is_file(), "{m}");
    }
}

#[test]
fn sweep_writes_optima_and_resumes() {
    let tmp = tempfile::tempdir().unwrap();
    let data = fixtures().join("images/sim");
    let out = tmp.path().join("sw");
    let args = [
        "keypoints",
        "sweep",
        "--data",
        data.to_str().unwrap(),
        "--combos",
        "SHITOMASI_SIFT,AKAZE_AKAZE",
        "--interpolations",
        "linear,area",
        "--widths",
        "512:1024:512",
        "--heights",
        "32,64",
        "--frames",
        "3",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ];
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&out.join("sweep.csv"));
    assert_eq!(rows.len(), 2 * 2 * 2 * 2);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(json["tasks_run"], 16, "{json}");
    assert!(json["optima"]["overall"]["cell"].is_string(), "{json}");
    assert!(json["optima"]["keypoints"]["value"].as_f64().unwrap() > 0.0);
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert!(
        md.contains("By interpolation") && md.contains("By resolution"),
        "{md}"
    );
    assert!(out.join("plots/linear-distinctiveness.png").is_file());
    let again = keylo(&args, tmp.path());
    assert!(again.status.success(), "{}", stderr(&again));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(
        (json["tasks_run"].as_u64(), json["tasks_resumed"].as_u64()),
        (Some(0), Some(16))
    );
    assert_eq!(read_csv(&out.join("sweep.csv")).len(), 16);
}

#[test]
fn bad_input_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("o");
    let out = out.to_str().unwrap();
    let data = fixtures().join("images/sim");
    let data = data.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut a = vec!["keypoints", "eval", "--out", out, "--no-plots"];
        a.extend_from_slice(extra);
        keylo(&a, tmp.path())
    };
    expect_failure(
        &run(&["--data", data, "--combos", "FAST_NOPE"]),
        2,
        "FAST_NOPE",
    );
    expect_failure(&run(&["--data", data, "--frames", "1"]), 2, "at least 2");
    expect_failure(&run(&["--data", "/no/such/dir"]), 2, "/no/such/dir");
    expect_failure(
        &run(&["--data", data, "--interpolation", "bicubic"]),
        2,
        "bicubic",
    );
    let cfg = tmp.path().join("eval.toml");
    std::fs::write(&cfg, "[metrics]\nblur_kernel = 4\n").unwrap();
    expect_failure(
        &run(&["--data", data, "--config", cfg.to_str().unwrap()]),
        2,
        "metrics.blur_kernel",
    );
    let broken = tmp.path().join("pngs");
    std::fs::create_dir_all(&broken).unwrap();
    std::fs::write(broken.join("a.png"), b"not a png").unwrap();
    std::fs::write(broken.join("b.png"), b"not a png").unwrap();
    expect_failure(&run(&["--data", broken.to_str().unwrap()]), 2, "a.png");
    // A named combination this build cannot make (SURF without the feature `nonfree`) is an
    // error; `paper` skips it with a note.
    expect_failure(
        &run(&["--data", data, "--combos", "SURF_SURF"]),
        2,
        "nonfree",
    );
}
