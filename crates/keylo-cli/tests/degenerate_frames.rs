//! Degenerate frames are never silent: a frame whose registration cannot constrain six
//! degrees of freedom (too few registered points, or a pose direction without information)
//! is warned about, flagged in frames.csv and summary.json, marked by `keylo compare`, stops
//! the run under `output.on_degenerate = "error"`, and a run of nothing else exits 4.

mod common;

use std::path::Path;

use common::{keylo, stderr};

/// A KITTI folder of `frames` scans, scan `k` being `points(k)` (x, y, z).
fn kitti(dir: &Path, frames: usize, points: impl Fn(usize) -> Vec<[f32; 3]>) {
    let velodyne = dir.join("velodyne");
    std::fs::create_dir_all(&velodyne).unwrap();
    for k in 0..frames {
        let mut bytes = Vec::new();
        for p in points(k) {
            for v in [p[0], p[1], p[2], 0.5] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        std::fs::write(velodyne.join(format!("{k:06}.bin")), bytes).unwrap();
    }
}

/// Scan `k` of a folder, as (x, y, z) points.
type Scans = dyn Fn(usize) -> Vec<[f32; 3]>;

/// A deterministic spread of `n` values in [-1, 1) (no random crate needed).
fn spread(i: usize, n: usize, salt: usize) -> f32 {
    ((i * 7919 + salt * 104_729) % n) as f32 / n as f32 * 2.0 - 1.0
}

fn run(data: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "run",
        "--data",
        data.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    keylo(&args, data.parent().unwrap())
}

fn read(out: &Path, file: &str) -> String {
    std::fs::read_to_string(out.join(file)).unwrap()
}

/// The `degenerate` column of frames.csv, one entry per frame.
fn flags(out: &Path) -> Vec<String> {
    let text = read(out, "frames.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "degenerate").unwrap();
    lines
        .map(|l| l.split(',').nth(col).unwrap_or_default().to_string())
        .collect()
}

#[test]
fn one_point_plane_line_and_duplicate_scans_are_reported_and_exit_4() {
    let tmp = tempfile::tempdir().unwrap();
    let n = 2000;
    let cases: [(&str, Box<Scans>, &str, usize); 4] = [
        (
            "one",
            Box::new(|_| vec![[5.0, 1.0, 0.5]]),
            "too-few-points",
            5,
        ),
        (
            "plane",
            Box::new(move |k| {
                let x = |i| 20.0 * spread(i, n, 1) + 0.1 * k as f32;
                (0..n)
                    .map(|i| [x(i), 20.0 * spread(i, n, 2), -1.5])
                    .collect()
            }),
            "no-information",
            4,
        ),
        (
            "line",
            Box::new(move |k| {
                let t = |i| 15.0 + 14.0 * spread(i, n, 3);
                (0..n)
                    .map(|i| [t(i) + 0.1 * k as f32, 0.5 * t(i), 0.2])
                    .collect()
            }),
            "no-information",
            4,
        ),
        (
            "duplicated",
            Box::new(|_| vec![[5.0, 1.0, 0.5]; 500]),
            "too-few-points",
            5,
        ),
    ];
    for (name, points, reason, flagged) in cases {
        let data = tmp.path().join(name);
        kitti(&data, 5, points);
        let out = tmp.path().join(format!("out-{name}"));
        let o = run(&data, &out, &[]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(4), "{name}: {e}");
        assert!(!e.contains("panicked"), "{e}");
        assert!(
            e.contains("frame 1 (") && e.contains("is degenerate"),
            "{name}: {e}"
        );
        assert!(
            e.contains("motion model's prediction, not odometry"),
            "{name}: {e}"
        );
        // The frames are written all the same, each flagged.
        let f = flags(&out);
        assert_eq!(f.len(), 5, "{name}");
        assert_eq!(
            f.iter().filter(|r| r.as_str() == reason).count(),
            flagged,
            "{name}: {f:?}"
        );
        let summary: serde_json::Value = serde_json::from_str(&read(&out, "summary.json")).unwrap();
        assert_eq!(summary["frames_degenerate"], flagged, "{name}");
        assert_eq!(summary["all_degenerate"], true, "{name}");
        assert_eq!(summary["degenerate"][0]["reason"], reason, "{name}");
        assert_eq!(read(&out, "trajectory.tum").lines().count(), 5, "{name}");
    }
}

#[test]
fn a_degenerate_frame_in_a_good_run_is_flagged_marked_by_compare_or_stops_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    // A room (six walls) seen from a sensor moving along x; scan 3 holds one point.
    let n = 3000;
    kitti(&data, 6, move |k| {
        if k == 3 {
            return vec![[5.0, 1.0, 0.5]];
        }
        (0..n)
            .map(|i| {
                let (u, v) = (spread(i, n, 5), spread(i, n, 7));
                let wall = [
                    [10.0, 6.0 * u, 2.0 * v],
                    [-10.0, 6.0 * u, 2.0 * v],
                    [10.0 * u, 6.0, 2.0 * v],
                    [10.0 * u, -6.0, 2.0 * v],
                    [10.0 * u, 6.0 * v, 2.0],
                    [10.0 * u, 6.0 * v, -2.0],
                ][i % 6];
                [wall[0] - 0.2 * k as f32, wall[1], wall[2]]
            })
            .collect()
    });
    let out = tmp.path().join("out");
    let o = run(&data, &out, &[]);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("frame 3 (") && e.contains("1 registered point, fewer than the 3"),
        "{e}"
    );
    assert!(!e.contains("frame 2 ("), "{e}");
    let f = flags(&out);
    assert_eq!(f, ["", "", "", "too-few-points", "", ""], "{f:?}");
    let summary: serde_json::Value = serde_json::from_str(&read(&out, "summary.json")).unwrap();
    assert_eq!(summary["frames_degenerate"], 1);
    assert_eq!(summary["all_degenerate"], false);
    assert_eq!(summary["degenerate"][0]["frame"], 3);
    assert_eq!(summary["degenerate"][0]["minimum"], 3);

    // `keylo compare` marks the run.
    let cmp = tmp.path().join("cmp");
    let o = keylo(
        &[
            "compare",
            "--data",
            data.to_str().unwrap(),
            "--out",
            cmp.to_str().unwrap(),
            "-q",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let md = read(&cmp, "compare.md");
    assert!(md.contains("ok (1 of 6 frames degenerate)"), "{md}");
    assert!(md.contains("**Degenerate frames**"), "{md}");
    let csv = read(&cmp, "compare.csv");
    assert!(
        csv.lines().next().unwrap().contains("degenerate_frames"),
        "{csv}"
    );

    // `output.on_degenerate = "error"`: stops at frame 3, frames 0–2 kept.
    let o = run(&data, &out, &["-q", "--set", "output.on_degenerate=error"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{e}");
    assert!(e.contains("stopped at frame 3: degenerate frame"), "{e}");
    assert_eq!(read(&out, "trajectory.tum").lines().count(), 3);
}
