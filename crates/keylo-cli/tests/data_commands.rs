//! `keylo info`, `keylo convert` and `--meta` on a real Ouster capture and on simulated data.

mod common;

use std::path::{Path, PathBuf};

use common::{expect_failure, keylo, small_sim, stderr, stdout};

fn ouster(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/fixtures/ouster")
        .join(name)
}

const PCAP: &str = "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";

#[test]
fn info_reports_an_ouster_capture_and_writes_its_images() {
    let tmp = tempfile::tempdir().unwrap();
    let pcap = ouster(PCAP);
    let out = tmp.path().join("img");
    let o = keylo(
        &[
            "info",
            pcap.to_str().unwrap(),
            "--image",
            "1",
            "--out",
            out.to_str().unwrap(),
            "--json",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let info: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(info["kind"], "ouster");
    assert_eq!(info["frames"], 3);
    assert_eq!(
        (info["rows"].as_u64(), info["cols"].as_u64()),
        (Some(128), Some(1024))
    );
    let details = info["details"].to_string();
    for want in ["OS-1-128", "RNG15_RFL8_NIR8", "1024x10", "122201000998"] {
        assert!(details.contains(want), "details lack {want}: {details}");
    }
    let channels = info["channels_with_data"].to_string();
    assert!(
        channels.contains("near-ir") && !channels.contains("signal"),
        "{channels}"
    );
    for c in ["range", "signal", "reflectivity", "near-ir"] {
        let png = out.join(format!("frame000001_{c}.png"));
        let bytes = std::fs::read(&png).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{}", png.display());
    }
}

#[test]
fn info_on_an_image_past_the_end_fails_clearly() {
    let tmp = tempfile::tempdir().unwrap();
    let pcap = ouster(PCAP);
    let out = tmp.path().join("img");
    let o = keylo(
        &[
            "info",
            pcap.to_str().unwrap(),
            "--image",
            "7",
            "--out",
            out.to_str().unwrap(),
        ],
        tmp.path(),
    );
    expect_failure(&o, 3, "--image 7: the data holds 3 frames");
}

#[test]
fn meta_names_the_metadata_of_a_capture_without_one_beside_it() {
    let tmp = tempfile::tempdir().unwrap();
    let pcap = tmp.path().join("capture.pcap");
    std::fs::copy(ouster(PCAP), &pcap).unwrap();
    let o = keylo(&["info", pcap.to_str().unwrap()], tmp.path());
    expect_failure(&o, 2, "--meta");
    let meta = ouster("OS-1-128_v2.3.0_1024x10_lb_n3.json");
    let o = keylo(
        &[
            "info",
            pcap.to_str().unwrap(),
            "--meta",
            meta.to_str().unwrap(),
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("frames                 3"),
        "{}",
        stdout(&o)
    );
    let o = keylo(
        &[
            "info",
            pcap.to_str().unwrap(),
            "--meta",
            "/nonexistent.json",
        ],
        tmp.path(),
    );
    expect_failure(&o, 2, "--meta /nonexistent.json: no such file");
}

#[test]
fn convert_writes_every_format_with_times() {
    let tmp = tempfile::tempdir().unwrap();
    let pcap = ouster(PCAP);
    for (format, file) in [
        ("ply", "000002.ply"),
        ("pcd", "000002.pcd"),
        ("kitti-bin", "velodyne/000002.bin"),
        ("frames", "keylo-frames.json"),
    ] {
        let out = tmp.path().join(format);
        let o = keylo(
            &[
                "convert",
                pcap.to_str().unwrap(),
                "--format",
                format,
                "--out",
                out.to_str().unwrap(),
            ],
            tmp.path(),
        );
        assert!(o.status.success(), "{format}: {}", stderr(&o));
        assert!(out.join(file).is_file(), "{format}: {file} missing");
        let times = std::fs::read_to_string(out.join("times.txt")).unwrap();
        let t: Vec<f64> = times.lines().map(|l| l.parse().unwrap()).collect();
        assert_eq!(t.len(), 3, "{format}");
        assert!(t[0] == 0.0 && (t[1] - 0.1).abs() < 0.01, "{format}: {t:?}");
    }
    // The frame folder reads back with the same frames as the capture.
    let o = keylo(
        &[
            "info",
            tmp.path().join("frames").to_str().unwrap(),
            "--json",
        ],
        tmp.path(),
    );
    let info: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(info["frames"], 3);
    // KITTI .bin: 16 bytes per point.
    let bin = std::fs::read(tmp.path().join("kitti-bin/velodyne/000000.bin")).unwrap();
    assert!(bin.len().is_multiple_of(16) && bin.len() > 16 * 50_000);
    // PCD header lists the default channels.
    let pcd = std::fs::read(tmp.path().join("pcd/000000.pcd")).unwrap();
    let header = String::from_utf8_lossy(&pcd[..300]);
    assert!(
        header.contains("FIELDS x y z intensity reflectivity ambient range ring t"),
        "{header}"
    );
}

#[test]
fn convert_checks_its_channels() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 2);
    let out = tmp.path().join("out");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "convert",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        keylo(&args, tmp.path())
    };
    expect_failure(
        &run(&["--format", "ply", "--channels", "colour"]),
        2,
        "unknown channel `colour`",
    );
    expect_failure(
        &run(&["--format", "kitti-bin", "--channels", "signal,range"]),
        2,
        "exactly one channel",
    );
    let o = run(&["--format", "ply", "--channels", "range,time"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let ply = std::fs::read(out.join("000001.ply")).unwrap();
    let header = String::from_utf8_lossy(&ply[..400]);
    assert!(
        header.contains("property float range\nproperty float t\nend_header"),
        "{header}"
    );
}

#[test]
fn frame_folders_take_start_stride_and_max_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("seq");
    small_sim(&data, 7);
    let frames = |sets: &[&str]| {
        let mut args = vec!["info", data.to_str().unwrap(), "--json"];
        for s in sets {
            args.extend_from_slice(&["--set", s]);
        }
        let o = keylo(&args, tmp.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let info: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
        info["frames"].as_u64().unwrap()
    };
    assert_eq!(frames(&[]), 7);
    assert_eq!(frames(&["source.stride=2"]), 4);
    assert_eq!(
        frames(&["source.start=1", "source.stride=3", "source.max_frames=5"]),
        2
    );
    let o = keylo(
        &["info", data.to_str().unwrap(), "--set", "source.stride=0"],
        tmp.path(),
    );
    expect_failure(&o, 2, "source.stride");
}

/// An unorganised source converts with every point, not one per image pixel, and `keylo
/// info` counts its points and the ones sharing a pixel.
#[test]
fn unorganised_scans_convert_with_every_point_and_info_counts_them() {
    let tmp = tempfile::tempdir().unwrap();
    let bin = tmp.path().join("bin");
    let o = keylo(
        &[
            "sim",
            "-q",
            "--scene",
            "road",
            "--frames",
            "2",
            "--format",
            "kitti-bin",
            "--out",
            bin.to_str().unwrap(),
            "--set",
            "sensor=os1-64",
            "--set",
            "columns=1024",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let velodyne = bin.join("velodyne");
    let first = std::fs::read_dir(&velodyne)
        .unwrap()
        .map(|e| e.unwrap().path())
        .min()
        .unwrap();
    let points = std::fs::metadata(&first).unwrap().len() / 16;
    // A coarse grid, so that many points share a pixel.
    let sets = ["--set", "source.projection.cols=256"];
    let mut args = vec!["info", velodyne.to_str().unwrap(), "--json"];
    args.extend(sets);
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let info: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let stats = &info["points"];
    let sharing = stats["mean_sharing"].as_f64().unwrap();
    assert!(
        stats["mean_points"].as_f64().unwrap() > 0.0 && sharing > 0.0,
        "{stats}"
    );
    let ply = tmp.path().join("ply");
    let mut args = vec![
        "convert",
        velodyne.to_str().unwrap(),
        "--format",
        "ply",
        "--out",
        ply.to_str().unwrap(),
    ];
    args.extend(sets);
    let o = keylo(&args, tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let header = std::fs::read(ply.join("000000.ply")).unwrap();
    let header = String::from_utf8_lossy(&header[..400.min(header.len())]).to_string();
    assert!(
        header.contains(&format!("element vertex {points}\n")),
        "{points} points expected: {header}"
    );
}
