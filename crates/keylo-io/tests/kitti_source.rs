//! `kind = "kitti"`: the real KITTI snippets in `shared/data/kitti_mini` (read in place;
//! skipped with a message when absent) and synthetic folders for the bad-input cases.

mod common;

use std::path::Path;

use common::{build, frames, kitti_mini, lit, write_bin};
use keylo_core::ScanPoints;
use keylo_io::kitti_bin::read_kitti_bin;

const NONE: u32 = ScanPoints::NONE;

/// The 12 numbers of every line of a KITTI pose file, as written (no re-orthonormalising).
fn raw_poses(path: &Path) -> Vec<[f64; 12]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            v.try_into().unwrap()
        })
        .collect()
}

#[test]
fn real_scans_stream_with_times_from_times_txt() {
    let Some(root) = kitti_mini() else { return };
    let mut src = build("kitti", &format!("path = {}", lit(&root.join("00")))).unwrap();
    let info = src.info();
    assert_eq!(info.frames, Some(10));
    assert!(
        info.description.contains("times.txt"),
        "{}",
        info.description
    );
    let first = src.next_frame().unwrap().unwrap();
    let scan = first.scan.as_ref().unwrap();
    assert_eq!(scan.len(), 124_668, "points of 00/000000.bin");
    assert_eq!(
        first.to_cloud().len(),
        124_668,
        "every point reaches the cloud"
    );
    assert_eq!((first.rows, first.cols, first.timestamp), (64, 2048, 0.0));
    let second = src.next_frame().unwrap().unwrap();
    assert_eq!((second.index, second.timestamp), (1, 0.1037359));
    assert!(
        src.ground_truth().is_none(),
        "no poses.txt in the snippet folder"
    );
}

#[test]
fn ground_truth_in_the_lidar_frame_matches_semantickitti_velo() {
    let Some(root) = kitti_mini() else { return };
    for seq in ["00", "01"] {
        let dir = root.join(seq);
        let params = format!(
            "path = {}\nposes = \"poses_semantickitti_cam0.txt\"",
            lit(&dir)
        );
        let src = build("kitti", &params).unwrap();
        assert!(src.info().description.contains("in the LiDAR frame"));
        let gt = src.ground_truth().unwrap();
        let want = raw_poses(&dir.join("poses_semantickitti_velo.txt"));
        assert_eq!(gt.len(), want.len());
        let mut worst = 0.0f64;
        for (pose, w) in gt.poses.iter().zip(&want) {
            let m = pose.to_homogeneous();
            for (k, expected) in w.iter().enumerate() {
                worst = worst.max((m[(k / 4, k % 4)] - expected).abs());
            }
        }
        eprintln!("{seq}: largest difference to poses_semantickitti_velo.txt: {worst:.2e}");
        assert!(worst < 1e-6, "{seq}: {worst}");
        let times = std::fs::read_to_string(dir.join("times.txt")).unwrap();
        let t1: f64 = times.lines().nth(1).unwrap().trim().parse().unwrap();
        assert_eq!(gt.stamps[1], t1, "{seq}: stamps from times.txt");
    }
}

#[test]
fn a_real_scan_projects_with_consistent_index_maps() {
    let Some(root) = kitti_mini() else { return };
    let scan = root.join("00/velodyne/000000.bin");
    let points = read_kitti_bin(&scan).unwrap();
    let mut src = build("kitti", &format!("path = {}", lit(&scan))).unwrap();
    let f = frames(src.as_mut()).unwrap().remove(0);
    let map = f.scan.as_ref().unwrap();
    assert_eq!(
        map.len(),
        points.len(),
        "a real scan has only finite points"
    );
    assert!(map
        .source_index
        .iter()
        .enumerate()
        .all(|(i, &s)| s as usize == i));
    let mapped = map.pixel.iter().filter(|&&p| p != NONE).count();
    let kept = f.valid_count();
    let n = points.len() as f64;
    eprintln!(
        "00/000000.bin: {} points, {:.1}% fall into the 64x1024 image, {:.1}% are kept \
         (the nearest of each pixel; {kept} of {} pixels filled)",
        points.len(),
        100.0 * mapped as f64 / n,
        100.0 * kept as f64 / n,
        f.rows * f.cols
    );
    assert!(mapped as f64 > 0.95 * n, "most points fall into the image");
    assert!(kept as f64 > 0.4 * n);
    for (pixel, &point) in map.pixel_to_point.iter().enumerate() {
        assert_eq!(f.valid[pixel], point != NONE, "pixel {pixel}");
        if point != NONE {
            assert_eq!(map.pixel[point as usize] as usize, pixel);
            let p = points[point as usize];
            assert_eq!(f.points[pixel].coords.as_slice(), &p[..3]);
            assert_eq!(f.signal[pixel], p[3]);
        }
    }
}

#[test]
fn velodyne_folder_selection_and_probes() {
    let Some(root) = kitti_mini() else { return };
    let velodyne = root.join("01/velodyne");
    let params = format!(
        "path = {}\nstart = 2\nstride = 3\nmax_frames = 2",
        lit(&velodyne)
    );
    let mut src = build("kitti", &params).unwrap();
    let f = frames(src.as_mut()).unwrap();
    assert_eq!(f.iter().map(|f| f.index).collect::<Vec<_>>(), vec![2, 5]);
    let times = std::fs::read_to_string(root.join("01/times.txt")).unwrap();
    let t5: f64 = times.lines().nth(5).unwrap().trim().parse().unwrap();
    assert_eq!(f[1].timestamp, t5, "times.txt of the parent of velodyne/");
    let r = common::registry();
    assert_eq!(r.detect_source(&root.join("00")), Some("kitti"));
    assert_eq!(r.detect_source(&velodyne), Some("kitti"));
    assert_eq!(r.detect_source(&velodyne.join("000000.bin")), Some("kitti"));
}

/// A synthetic sequence: `n` scans of 3 points, `velodyne/` layout.
fn sequence(n: usize) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let v = dir.path().join("velodyne");
    std::fs::create_dir_all(&v).unwrap();
    for i in 0..n {
        let pts = [
            [5.0, 0.0, 0.0, 0.1],
            [0.0, 5.0, -1.0, 0.2],
            [-5.0, 0.0, 0.1, i as f32],
        ];
        write_bin(&v.join(format!("{i:06}.bin")), &pts);
    }
    dir
}

fn open_err(dir: &Path, extra: &str) -> String {
    match build("kitti", &format!("path = {}\n{extra}", lit(dir))) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("expected an error opening {}", dir.display()),
    }
}

const IDENTITY: &str = "1 0 0 0 0 1 0 0 0 0 1 0";

#[test]
fn synthetic_folders_use_the_rate_and_natural_order() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["10.bin", "9.bin", "100.bin"] {
        write_bin(&dir.path().join(name), &[[1.0, 0.0, 0.0, 0.5]]);
    }
    let params = format!("path = {}\nframe_rate_hz = 4", lit(dir.path()));
    let mut src = build("kitti", &params).unwrap();
    assert!(src.info().description.contains("index / 4 Hz"));
    let f = frames(src.as_mut()).unwrap();
    assert_eq!(
        f.iter().map(|f| f.timestamp).collect::<Vec<_>>(),
        vec![0.0, 0.25, 0.5]
    );
}

#[test]
fn empty_folders_and_bad_side_files_are_errors_naming_the_file() {
    let empty = tempfile::tempdir().unwrap();
    let e = open_err(empty.path(), "");
    assert!(e.contains("no .bin scans"), "{e}");

    let seq = sequence(3);
    std::fs::write(seq.path().join("times.txt"), "0.0\n0.1\n").unwrap();
    let e = open_err(seq.path(), "");
    assert!(e.contains("times.txt: 2 times for 3 scans"), "{e}");
    std::fs::write(seq.path().join("times.txt"), "0.0\n0.1\n0.2\n").unwrap();

    std::fs::write(
        seq.path().join("poses.txt"),
        format!("{IDENTITY}\n{IDENTITY}\n{IDENTITY}\n"),
    )
    .unwrap();
    let src = build("kitti", &format!("path = {}", lit(seq.path()))).unwrap();
    assert!(src.ground_truth().is_none());
    assert!(src.info().description.contains("not used: no calib.txt"));
    let e = open_err(seq.path(), "poses = \"poses.txt\"");
    assert!(e.contains("poses.txt: cam0 poses need calib.txt"), "{e}");
    let e = open_err(seq.path(), "poses = \"missing.txt\"");
    assert!(
        e.contains("missing.txt: `source.poses`: no such file"),
        "{e}"
    );

    std::fs::write(
        seq.path().join("calib.txt"),
        format!("P0: 1 0 0\nTr {IDENTITY}\n"),
    )
    .unwrap();
    let e = open_err(seq.path(), "");
    assert!(
        e.contains("calib.txt: line 2: expected `KEY: numbers`"),
        "{e}"
    );
    std::fs::write(seq.path().join("calib.txt"), "Tr: 1 0 0 0 0 1 0 0 0 0 1\n").unwrap();
    let e = open_err(seq.path(), "");
    assert!(
        e.contains("calib.txt: line 1: expected 12 numbers, found 11"),
        "{e}"
    );
    std::fs::write(seq.path().join("calib.txt"), format!("Tr: {IDENTITY}\n")).unwrap();

    std::fs::write(
        seq.path().join("poses.txt"),
        format!("{IDENTITY}\n1 0 0 0 0 1 0 0 0 0 1\n{IDENTITY}\n"),
    )
    .unwrap();
    let e = open_err(seq.path(), "");
    assert!(
        e.contains("poses.txt: line 2: expected 12 numbers, found 11"),
        "{e}"
    );
    std::fs::write(
        seq.path().join("poses.txt"),
        format!("{IDENTITY}\n{IDENTITY}\n"),
    )
    .unwrap();
    let e = open_err(seq.path(), "");
    assert!(e.contains("poses.txt: 2 poses for 3 scans"), "{e}");
    std::fs::write(
        seq.path().join("poses.txt"),
        format!("{IDENTITY}\n{IDENTITY}\n{IDENTITY}\n"),
    )
    .unwrap();
    let src = build("kitti", &format!("path = {}", lit(seq.path()))).unwrap();
    assert_eq!(src.ground_truth().unwrap().stamps, vec![0.0, 0.1, 0.2]);
}

#[test]
fn a_bin_of_the_wrong_size_fails_on_its_own_frame() {
    let seq = sequence(3);
    std::fs::write(seq.path().join("velodyne/000001.bin"), [0u8; 20]).unwrap();
    let mut src = build("kitti", &format!("path = {}", lit(seq.path()))).unwrap();
    assert!(src.next_frame().unwrap().is_ok());
    let e = src.next_frame().unwrap().unwrap_err().to_string();
    assert!(
        e.contains("000001.bin: size 20 is not a multiple of 16"),
        "{e}"
    );
    let third = src.next_frame().unwrap().unwrap();
    assert_eq!(third.index, 2);
    assert!(src.next_frame().is_none());
}
