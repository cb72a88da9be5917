//! `keylo run --map-out` and `[output] pose_graph`, then `keylo map info|export|crop` as a
//! user runs them, and their errors (docs/maps.md).

mod common;

use common::{expect_failure, keylo, keylo_line, small_sim, stdout};

#[test]
fn a_run_saves_a_map_and_a_pose_graph_and_map_commands_use_it() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    small_sim(&data, 12);
    let d = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    let o = keylo(
        &[
            "run",
            "--data",
            &d("data"),
            "--out",
            &d("run"),
            "--map-out",
            &d("map"),
            "-q",
            "--set",
            "output.pose_graph=true",
            "--set",
            "map.keyframe_distance=0.1",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("run/summary.json")).unwrap(),
    )
    .unwrap();
    let points = summary["map"]["points"].as_u64().unwrap();
    let keyframes = summary["map"]["keyframes"].as_u64().unwrap();
    assert!(points > 1000 && keyframes >= 3, "{summary}");

    // The graph's vertices are the map's keyframes, one edge between each pair.
    let g2o = std::fs::read_to_string(dir.path().join("run/pose_graph.g2o")).unwrap();
    let vertices: Vec<&str> = g2o
        .lines()
        .filter(|l| l.starts_with("VERTEX_SE3:QUAT"))
        .collect();
    let edges: Vec<&str> = g2o
        .lines()
        .filter(|l| l.starts_with("EDGE_SE3:QUAT"))
        .collect();
    assert_eq!(
        (vertices.len() as u64, edges.len() as u64),
        (keyframes, keyframes - 1)
    );
    let csv = std::fs::read_to_string(dir.path().join("map/keyframes.csv")).unwrap();
    let row1: Vec<&str> = csv.lines().nth(2).unwrap().split(',').collect();
    let v1: Vec<&str> = vertices[1].split_whitespace().collect();
    assert_eq!(
        v1[2].parse::<f64>().unwrap(),
        row1[3].parse::<f64>().unwrap()
    );
    assert!(edges
        .iter()
        .all(|e| e.split_whitespace().count() == 3 + 7 + 21));

    let info = keylo(&["map", "info", &d("map")], dir.path());
    assert!(info.status.success());
    assert!(
        stdout(&info).contains(&format!("points       {points} (voxel 0.2 m)")),
        "{}",
        stdout(&info)
    );
    let export = keylo(&["map", "export", &d("map"), &d("all.pcd")], dir.path());
    assert!(stdout(&export).contains(&format!("wrote {points} points")));
    let crop = keylo(
        &[
            "map",
            "crop",
            &d("map"),
            "--min",
            "-2,-2,-2",
            "--max",
            "2,2,2",
            "--out",
            &d("crop"),
        ],
        dir.path(),
    );
    assert!(crop.status.success(), "{}", common::stderr(&crop));
    let cropped = keylo(&["map", "info", "--json", &d("crop")], dir.path());
    let m: serde_json::Value = serde_json::from_str(&stdout(&cropped)).unwrap();
    assert!(m["points"].as_u64().unwrap() < points);
    assert_eq!(m["cropped_from"].as_str().unwrap(), d("map"));
}

#[test]
fn bad_maps_and_settings_are_errors_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    expect_failure(
        &keylo(&["map", "info", &d("nowhere")], dir.path()),
        2,
        "nowhere: no such map folder",
    );
    std::fs::create_dir(dir.path().join("empty")).unwrap();
    expect_failure(
        &keylo(&["map", "info", &d("empty")], dir.path()),
        2,
        "this folder is not a keylo map",
    );
    // Run in the temporary folder: relative paths.
    let run = |extra: &str| {
        keylo_line(
            &format!("run --set source.frames=2 --out r {extra}"),
            dir.path(),
        )
    };
    expect_failure(
        &run("--map-out m --set map.voxel_size=-1"),
        2,
        "map.voxel_size = -1: expected a finite value above 0",
    );
    assert!(
        !dir.path().join("m").exists(),
        "nothing is written before the settings are checked"
    );
    expect_failure(
        &run("--set output.covariance_sigma_m=-1"),
        2,
        "output.covariance_sigma_m",
    );
    // The pose graph's keyframes come from [map] too: checked before the run writes anything.
    let graph = run("--set output.pose_graph=true --set map.keyframe_distance=-1");
    expect_failure(&graph, 2, "map.keyframe_distance = -1");
    assert!(
        !dir.path().join("r").exists(),
        "nothing is written before [map] is checked"
    );
    let crop = keylo_line("map crop empty --min 1,1,1 --max 0,0,0 --out c", dir.path());
    expect_failure(&crop, 2, "lies above --max");
}

#[test]
fn a_run_is_localised_in_its_own_map_and_bad_poses_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    small_sim(&dir.path().join("data"), 10);
    let o = keylo_line("run --data data --out run --map-out map -q", dir.path());
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = keylo_line(
        "localise map --data data --out loc --set localise.voxel_size=0.3",
        dir.path(),
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(stdout(&o).contains("10 frames in map"), "{}", stdout(&o));
    let rows = common::read_csv(&dir.path().join("loc/localise.csv"));
    assert_eq!(rows.len(), 10);
    assert!(rows.iter().all(|r| r["tracking"] == "true"), "{rows:?}");
    let tum = std::fs::read_to_string(dir.path().join("loc/trajectory.tum")).unwrap();
    assert_eq!(tum.lines().filter(|l| !l.starts_with('#')).count(), 10);

    let bad = |pose: &str, needle: &str| {
        let o = keylo(
            &[
                "localise",
                "map",
                "--data",
                "data",
                "--out",
                "x",
                "--initial-pose",
                pose,
            ],
            dir.path(),
        );
        expect_failure(&o, 2, needle);
    };
    bad("1 2 3", "3 numbers; expected seven");
    bad("0 0 0 0 0 0 2", "the quaternion's norm is 2");
    bad("0 0 0 0 0 x 1", "expected seven numbers");
    bad("500 0 0 0 0 0 1", "lies outside the map");
    let o = keylo_line(
        "localise map --data data --out x --set localise.min_fitness=2",
        dir.path(),
    );
    expect_failure(&o, 2, "localise.min_fitness = 2: expected 0..=1");
    let o = keylo_line("localise nowhere --data data --out x", dir.path());
    expect_failure(&o, 2, "nowhere: no such map folder");

    // A frame the source cannot read stops the run as `keylo run` stops: exit 3, the
    // frames before it kept in trajectory.tum and localise.csv.
    let cut = dir.path().join("cut");
    std::fs::create_dir_all(cut.join("frames")).unwrap();
    for entry in std::fs::read_dir(dir.path().join("data")).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() {
            std::fs::copy(&path, cut.join(path.file_name().unwrap())).unwrap();
        }
    }
    for entry in std::fs::read_dir(dir.path().join("data/frames")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, cut.join("frames").join(path.file_name().unwrap())).unwrap();
    }
    let bad_frame = std::fs::File::options()
        .write(true)
        .open(cut.join("frames/000006.klf"))
        .unwrap();
    bad_frame.set_len(100).unwrap();
    let o = keylo_line(
        "localise map --data cut --out cut-loc --set localise.voxel_size=0.3",
        dir.path(),
    );
    expect_failure(&o, 3, "stopped at frame 6: ");
    assert!(
        common::stderr(&o).contains("the 6 frames done before it are written to cut-loc"),
        "{}",
        common::stderr(&o)
    );
    assert_eq!(
        common::read_csv(&dir.path().join("cut-loc/localise.csv")).len(),
        6
    );
    let tum = std::fs::read_to_string(dir.path().join("cut-loc/trajectory.tum")).unwrap();
    assert_eq!(tum.lines().filter(|l| !l.starts_with('#')).count(), 6);
}
