//! Sharded studies: `--shard I/N` on `keylo compare`, `keylo keypoints eval` and `sweep`, and
//! their `merge`, give the tables of one process (all but the timing columns); resume; and
//! shards that do not make one study are refused by name.

mod common;

use std::path::{Path, PathBuf};

use common::{config, expect_failure, keylo, read_csv, small_sim, stderr};
use serde_json::Value;

fn read_json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn run_ok(args: &[String], cwd: &Path) -> String {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = keylo(&args, cwd);
    assert!(
        o.status.success(),
        "keylo {}: {}",
        args.join(" "),
        stderr(&o)
    );
    stderr(&o)
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

fn path(p: &Path) -> String {
    p.display().to_string()
}

/// `study` followed by `extra`.
fn extended(study: &[String], extra: &[&str]) -> Vec<String> {
    let mut a = study.to_vec();
    a.extend(strings(extra));
    a
}

/// `v` without the keys that time or resources decide.
fn untimed(mut v: Value, timing: &[&str]) -> Value {
    if let Some(map) = v.as_object_mut() {
        for k in timing {
            map.remove(*k);
        }
    }
    v
}

#[test]
fn compare_shards_merge_into_the_tables_of_one_process_and_bad_sets_are_named() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 6);
    let study = strings(&[
        "compare",
        &config("paper/raw-kiss-icp.toml"),
        &config("examples/corridor-voxel-kiss-icp.toml"),
        "--grid",
        "registrar.voxel_size=0.5,1.0",
        "--data",
        &path(&data),
        "--no-plots",
        "-q",
    ]);
    let with = |extra: &[&str]| extended(&study, extra);
    run_ok(&with(&["--out", "single", "--jobs", "2"]), tmp.path());
    let shards: Vec<PathBuf> = (0..3).map(|i| tmp.path().join(format!("s{i}"))).collect();
    let mut items = 0;
    for (i, dir) in shards.iter().enumerate() {
        run_ok(
            &with(&["--out", &path(dir), "--shard", &format!("{i}/3")]),
            tmp.path(),
        );
        let m = read_json(&dir.join("shard.json"));
        assert_eq!(m["complete"], true, "{m}");
        items += m["items"].as_array().unwrap().len();
    }
    assert_eq!(items, 4, "every run in exactly one shard");
    // A shard run again skips its finished runs.
    let again = run_ok(
        &with(&["--out", &path(&shards[0]), "--shard", "0/3"]),
        tmp.path(),
    );
    assert!(!again.contains("panicked"), "{again}");
    let m = read_json(&shards[0].join("shard.json"));
    assert!(m["results"]
        .as_object()
        .unwrap()
        .values()
        .all(|o| o["resumed"] == true));
    // A shard killed mid-run (its manifest incomplete, one run without its summary) runs
    // that run again and only that one.
    let mut m = read_json(&shards[1].join("shard.json"));
    let victim = m["items"][0].as_str().unwrap().to_string();
    m["complete"] = Value::Bool(false);
    m["results"].as_object_mut().unwrap().remove(&victim);
    std::fs::write(shards[1].join("shard.json"), m.to_string()).unwrap();
    std::fs::remove_file(shards[1].join("runs").join(&victim).join("summary.json")).unwrap();
    run_ok(
        &with(&["--out", &path(&shards[1]), "--shard", "1/3"]),
        tmp.path(),
    );
    let m = read_json(&shards[1].join("shard.json"));
    assert_eq!(m["complete"], true, "{m}");
    for (id, o) in m["results"].as_object().unwrap() {
        assert_eq!(o["resumed"], *id != victim, "{id}: {o}");
    }
    let merge = |out: &str, dirs: &[&PathBuf]| {
        let mut a = strings(&["compare", "merge", out]);
        a.extend(dirs.iter().map(|d| path(d)));
        a
    };
    run_ok(
        &merge("merged", &[&shards[2], &shards[0], &shards[1]]),
        tmp.path(),
    );
    let timing = [
        "cpu_percent",
        "peak_rss_mb",
        "odometry_hz",
        "rate_vs_raw",
        "resumed",
    ];
    let single = read_json(&tmp.path().join("single/compare.json"));
    let merged = read_json(&tmp.path().join("merged/compare.json"));
    let rows = |v: &Value| -> Vec<Value> {
        v["runs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| untimed(r.clone(), &timing))
            .collect()
    };
    assert_eq!(rows(&single).len(), 4);
    assert_eq!(rows(&single), rows(&merged));
    assert_eq!(single["criterion"], merged["criterion"]);
    let note = read_json(&tmp.path().join("merged/merged.json"));
    assert_eq!(note["shards"].as_array().unwrap().len(), 3, "{note}");

    // Shards that are not one whole study.
    let o = |args: Vec<String>| {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        keylo(&a, tmp.path())
    };
    expect_failure(
        &o(merge("m2", &[&shards[0], &shards[1]])),
        2,
        "shard(s) 2/3 of study",
    );
    expect_failure(
        &o(merge("m2", &[&shards[0], &shards[0], &shards[1]])),
        2,
        "given twice",
    );
    // A shard of another study (one config fewer) into a taken folder: refused, untouched.
    let before = std::fs::read_to_string(shards[1].join("shard.json")).unwrap();
    let other = strings(&[
        "compare",
        &config("paper/raw-kiss-icp.toml"),
        "--data",
        &path(&data),
        "--no-plots",
        "-q",
        "--shard",
        "1/3",
        "--out",
        &path(&shards[1]),
    ]);
    expect_failure(&o(other.clone()), 2, "another study");
    assert_eq!(
        std::fs::read_to_string(shards[1].join("shard.json")).unwrap(),
        before
    );
    let foreign = tmp.path().join("foreign");
    let mut other = other;
    let n = other.len();
    other[n - 1] = path(&foreign);
    other[n - 3] = "0/1".into();
    run_ok(&other, tmp.path());
    expect_failure(
        &o(merge("m3", &[&shards[0], &shards[1], &foreign])),
        2,
        "different studies",
    );
    expect_failure(&o(with(&["--out", "x", "--shard", "3/3"])), 2, "0 to 2");
    // A shard that did not finish (killed): merge says which and how to go on.
    let mut m = read_json(&shards[2].join("shard.json"));
    m["complete"] = Value::Bool(false);
    std::fs::write(shards[2].join("shard.json"), m.to_string()).unwrap();
    expect_failure(
        &o(merge("m4", &[&shards[0], &shards[1], &shards[2]])),
        2,
        "is incomplete",
    );
    // A folder of an older keylo.
    m["format"] = Value::from("keylo-shard/0");
    std::fs::write(shards[2].join("shard.json"), m.to_string()).unwrap();
    expect_failure(
        &o(merge("m5", &[&shards[0], &shards[1], &shards[2]])),
        2,
        "keylo-shard/0",
    );
}

/// A PNG folder of `n` images cycling through the simulated fixtures.
fn images(dir: &Path, n: usize) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/kpeval/images/sim");
    let mut pngs: Vec<PathBuf> = std::fs::read_dir(&src)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    pngs.sort();
    let out = dir.join("images");
    std::fs::create_dir_all(&out).unwrap();
    for i in 0..n {
        std::fs::copy(&pngs[i % pngs.len()], out.join(format!("img{i:03}.png"))).unwrap();
    }
    out
}

#[test]
fn keypoint_eval_shards_merge_into_the_rows_of_one_process() {
    let tmp = tempfile::tempdir().unwrap();
    // 27 images: two blocks per detector, the second starting from its pair in the first.
    let data = images(tmp.path(), 27);
    let study = strings(&[
        "keypoints",
        "eval",
        "--data",
        &path(&data),
        "--combos",
        "ORB_ORB,FAST_BRIEF,FAST_ORB",
        "--width",
        "512",
        "--no-plots",
        "-q",
    ]);
    let with = |extra: &[&str]| extended(&study, extra);
    run_ok(&with(&["--out", "single"]), tmp.path());
    for i in 0..2 {
        run_ok(
            &with(&["--out", &format!("s{i}"), "--shard", &format!("{i}/2")]),
            tmp.path(),
        );
    }
    run_ok(
        &strings(&["keypoints", "eval", "merge", "merged", "s1", "s0"]),
        tmp.path(),
    );
    let timing = ["detect_ms", "describe_ms", "match_ms", "time_ms"];
    let rows = |dir: &str| -> Vec<_> {
        read_csv(&tmp.path().join(dir).join("per_image.csv"))
            .into_iter()
            .map(|mut r| {
                for t in timing {
                    r.remove(t);
                }
                r
            })
            .collect()
    };
    let single = rows("single");
    assert_eq!(single.len(), 27 * 3);
    assert!(single
        .iter()
        .any(|r| r["index"] == "25" && !r["matches"].is_empty()));
    assert_eq!(single, rows("merged"));
    let summary = |dir: &str| {
        let v = read_json(&tmp.path().join(dir).join("summary.json"));
        v["combos"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                let mut c = c.clone();
                let metrics = c["metrics"].as_array_mut().unwrap();
                metrics.retain(|m| m[0] != "time_ms");
                c
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(summary("single"), summary("merged"));
    // A killed eval shard (one item's rows not recorded) does that item again.
    let manifest = tmp.path().join("s1/shard.json");
    let mut m = read_json(&manifest);
    let victim = m["items"][0].as_str().unwrap().to_string();
    m["complete"] = Value::Bool(false);
    m["results"].as_object_mut().unwrap().remove(&victim);
    std::fs::write(&manifest, m.to_string()).unwrap();
    run_ok(&with(&["--out", "s1", "--shard", "1/2"]), tmp.path());
    let again = read_json(&manifest);
    assert_eq!(again["complete"], true);
    for (id, r) in m["results"].as_object().unwrap() {
        // Finished items were not evaluated again: their recorded times are unchanged.
        assert_eq!(again["results"][id]["seconds"], r["seconds"], "{id}");
    }
    assert!(again["results"][&victim]["rows"].is_array());
    run_ok(
        &strings(&["keypoints", "eval", "merge", "merged2", "s0", "s1"]),
        tmp.path(),
    );
    assert_eq!(single, rows("merged2"));
    let o = keylo(&["keypoints", "eval", "merge", "m2", "s0"], tmp.path());
    expect_failure(&o, 2, "missing");
    let o = keylo(
        &["keypoints", "sweep", "merge", "m2", "s0", "s1"],
        tmp.path(),
    );
    expect_failure(&o, 2, "not of `keylo keypoints sweep`");
}

#[test]
fn keypoint_sweep_shards_merge_into_the_results_of_one_process() {
    let tmp = tempfile::tempdir().unwrap();
    let data = images(tmp.path(), 3);
    let study = strings(&[
        "keypoints",
        "sweep",
        "--data",
        &path(&data),
        "--combos",
        "ORB_ORB,FAST_BRIEF",
        "--interpolations",
        "linear,area",
        "--widths",
        "256,512",
        "--heights",
        "32,64",
        "--no-plots",
        "-q",
    ]);
    let with = |extra: &[&str]| extended(&study, extra);
    run_ok(&with(&["--out", "single"]), tmp.path());
    for i in 0..3 {
        run_ok(
            &with(&["--out", &format!("s{i}"), "--shard", &format!("{i}/3")]),
            tmp.path(),
        );
    }
    run_ok(
        &strings(&["keypoints", "sweep", "merge", "merged", "s0", "s1", "s2"]),
        tmp.path(),
    );
    let results = |dir: &str| {
        let v = read_json(&tmp.path().join(dir).join("sweep.json"));
        v["results"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                let mut r = r.clone();
                r["means"]
                    .as_array_mut()
                    .unwrap()
                    .retain(|m| m[0] != "time_ms");
                r
            })
            .collect::<Vec<_>>()
    };
    let single = results("single");
    assert_eq!(single.len(), 2 * 2 * 2 * 2);
    assert_eq!(single, results("merged"));
    let optima = |dir: &str| {
        let mut v = read_json(&tmp.path().join(dir).join("sweep.json"))["optima"].clone();
        v.as_object_mut().unwrap().remove("time_ms");
        v
    };
    assert_eq!(optima("single"), optima("merged"));
}
