//! A reference whose clock is not keylo's (frame indices instead of seconds): `keylo eval` and
//! `keylo compare` say how few poses associate and why, `--gt-time-scale` /
//! `--gt-time-offset` fix it, and plots name the reference by `--gt-label`.

mod common;

use std::path::Path;

use common::{keylo, keylo_line, small_sim, stderr, stdout};

fn read_json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The options a warning suggests (`try --gt-time-scale S [--gt-time-offset O]`).
fn suggested(warning: &str) -> Vec<String> {
    let tail = warning
        .split("try ")
        .nth(1)
        .unwrap_or_else(|| panic!("no suggestion in: {warning}"));
    tail.lines()
        .next()
        .unwrap_or("")
        .split_whitespace()
        .map(String::from)
        .collect()
}

/// A curved path at 10 Hz, as TUM text, its stamps in seconds or frame indices.
fn path(frames: bool, stretch: f64) -> String {
    (0..154)
        .map(|i| {
            let t = i as f64 * 0.1;
            let stamp = if frames {
                format!("{i}")
            } else {
                format!("{t:.6}")
            };
            let (x, y, z) = (stretch * t * 2.0, t.sin(), 0.1 * t.cos());
            format!("{stamp} {x} {y} {z} 0 0 0 1\n")
        })
        .collect()
}

/// The TUM file at `gt` with each stamp replaced by its pose's index.
fn frame_indexed(gt: &Path) -> String {
    std::fs::read_to_string(gt)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .enumerate()
        .map(|(i, l)| format!("{i} {}\n", l.split_once(' ').unwrap().1))
        .collect()
}

#[test]
fn eval_names_a_frame_index_reference_and_the_scale_fixes_it() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("gt.tum"), path(false, 1.0)).unwrap();
    std::fs::write(tmp.path().join("frames.tum"), path(true, 1.0)).unwrap();
    std::fs::write(tmp.path().join("est.tum"), path(false, 1.02)).unwrap();
    let o = keylo_line("eval --est est.tum --gt frames.tum --json", tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let (err, out) = (stderr(&o), stdout(&o));
    assert!(
        err.contains("warning: only 16 of 154 estimated poses (10 %) associate with frames.tum")
            && err.contains("frames.tum times 0.000 … 153.000 s")
            && err.contains("frame indices"),
        "{err}"
    );
    assert_eq!(suggested(&err), ["--gt-time-scale", "0.1"]);
    assert!(
        out.contains("associated / estimated             16/154"),
        "{out}"
    );
    let json = |text: &str| -> serde_json::Value {
        serde_json::from_str(&text[text.find('{').unwrap()..]).unwrap()
    };
    let low = json(&out);
    assert_eq!(low["association"]["associated"], 16);
    assert_eq!(low["association"]["likely_cause"]["kind"], "frame-indices");

    let fixed = keylo_line(
        "eval --est est.tum --gt frames.tum --json --gt-time-scale 0.1",
        tmp.path(),
    );
    assert!(!stderr(&fixed).contains("warning"), "{}", stderr(&fixed));
    let right = keylo_line("eval --est est.tum --gt gt.tum --json", tmp.path());
    let (fixed, right) = (json(&stdout(&fixed)), json(&stdout(&right)));
    assert_eq!(fixed["association"]["associated"], 154);
    let ate = |v: &serde_json::Value| v["ate_rmse_m"].as_f64().unwrap();
    assert!(
        (ate(&fixed) - ate(&right)).abs() < 1e-9,
        "{fixed} vs {right}"
    );

    let bad = keylo_line(
        "eval --est est.tum --gt gt.tum --gt-time-scale -1",
        tmp.path(),
    );
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("--gt-time-scale"), "{}", stderr(&bad));
}

#[test]
fn compare_says_why_few_poses_pair_and_the_suggested_options_fix_it() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 8);
    let frames = frame_indexed(&data.join("gt.tum"));
    let frames_path = tmp.path().join("frames.tum");
    std::fs::write(&frames_path, frames).unwrap();
    let compare = |out: &str, gt: &Path, extra: &[String]| {
        let mut args = vec![
            "compare".to_string(),
            "--data".into(),
            data.display().to_string(),
            "--gt".into(),
            gt.display().to_string(),
            "--out".into(),
            tmp.path().join(out).display().to_string(),
        ];
        args.extend(extra.iter().cloned());
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = keylo(&args, tmp.path());
        assert!(o.status.success(), "{}", stderr(&o));
        (
            stderr(&o),
            read_json(&tmp.path().join(out).join("compare.json")),
        )
    };
    let (err, low) = compare("low", &frames_path, &["--no-plots".into()]);
    let run = &low["runs"][0];
    assert_eq!(run["associated"], "0/8", "{run}");
    assert_eq!(run["reference"], "frames.tum");
    assert!(
        run["reason"].as_str().unwrap().contains("poor association"),
        "{run}"
    );
    assert_eq!(err.matches("warning: seq: only 0 of 8").count(), 1, "{err}");
    let md = std::fs::read_to_string(tmp.path().join("low/compare.md")).unwrap();
    assert!(
        md.contains("**Warning (seq):** only 0 of 8") && md.contains("frame indices"),
        "{md}"
    );
    let csv = std::fs::read_to_string(tmp.path().join("low/compare.csv")).unwrap();
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .ends_with(",associated,reference"),
        "{csv}"
    );

    let mut fix = suggested(low["warnings"][0]["text"].as_str().unwrap());
    assert_eq!(fix[..2], ["--gt-time-scale", "0.1"]);
    assert_eq!(fix[2], "--gt-time-offset", "{fix:?}");
    fix.extend(["--gt-label".into(), "frames (rescaled)".into()]);
    let (err, fixed) = compare("fixed", &frames_path, &fix);
    assert!(!err.contains("warning"), "{err}");
    let (_, right) = compare("right", &data.join("gt.tum"), &["--no-plots".into()]);
    let (fixed, right) = (&fixed["runs"][0], &right["runs"][0]);
    assert_eq!(fixed["associated"], "8/8", "{fixed}");
    let ate = |v: &serde_json::Value| v["trans_rmse_m"].as_f64().unwrap();
    assert!((ate(fixed) - ate(right)).abs() < 1e-9, "{fixed} vs {right}");
    assert_eq!(right["reference"], "gt.tum");
    let svg = std::fs::read_to_string(tmp.path().join("fixed/plots/seq/trajectories.svg")).unwrap();
    assert!(svg.contains("frames (rescaled)") && !svg.contains("ground truth"));
}

/// `keylo run --gt` with a frame-index reference: the warning on stderr and in summary.json,
/// and `--gt-time-scale`/`--gt-time-offset` as suggested give every pose its partner.
#[test]
fn run_warns_of_a_frame_index_reference_and_the_options_fix_it() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("data");
    small_sim(&data, 8);
    let frames = frame_indexed(&data.join("gt.tum"));
    std::fs::write(tmp.path().join("frames.tum"), frames).unwrap();
    let o = keylo_line("run --data data --gt frames.tum --out low -q", tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let warning = read_json(&tmp.path().join("low/summary.json"))["association_warning"]
        .as_str()
        .map(String::from)
        .unwrap_or_else(|| panic!("no association_warning: {}", stderr(&o)));
    assert!(warning.contains("frame indices"), "{warning}");
    assert!(stderr(&o).contains("estimated poses"), "{}", stderr(&o));
    let mut args = vec![
        "run",
        "--data",
        "data",
        "--gt",
        "frames.tum",
        "--out",
        "fixed",
        "-q",
    ];
    let fix = suggested(&warning);
    args.extend(fix.iter().map(String::as_str));
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let fixed = read_json(&tmp.path().join("fixed/summary.json"));
    assert!(fixed.get("association_warning").is_none(), "{fixed}");
    assert_eq!(fixed["accuracy"]["associated_poses"], 8);
}
