//! keylo's Ouster metadata parser against ouster-sdk 1.0.1 on the eight sample files (both
//! layouts, with and without `data_format`). The golden values were written by
//! `tests/fixtures/ouster/make_metadata_golden.py`, which runs ouster-sdk.

use std::path::{Path, PathBuf};

use keylo_io::ouster::{OusterMetadata, UdpProfile};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ouster")
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-9 * (1.0 + y.abs()))
}

#[test]
fn metadata_matches_ouster_sdk_on_every_sample() {
    let golden: Value = serde_json::from_str(
        &std::fs::read_to_string(fixtures().join("metadata_golden.json")).unwrap(),
    )
    .unwrap();
    let files = golden["files"].as_object().unwrap();
    assert_eq!(files.len(), 8);
    for (name, g) in files {
        let m = OusterMetadata::read(&fixtures().join(name)).unwrap();
        let ctx = |field: &str| format!("{name}: {field}");
        assert_eq!(
            m.columns_per_frame as u64,
            g["columns_per_frame"].as_u64().unwrap(),
            "{}",
            ctx("columns_per_frame")
        );
        assert_eq!(
            m.pixels_per_column as u64,
            g["pixels_per_column"].as_u64().unwrap(),
            "{}",
            ctx("pixels_per_column")
        );
        assert_eq!(
            m.columns_per_packet as u64,
            g["columns_per_packet"].as_u64().unwrap(),
            "{}",
            ctx("columns_per_packet")
        );
        let window = g["column_window"].as_array().unwrap();
        assert_eq!(
            (m.column_window.0 as u64, m.column_window.1 as u64),
            (window[0].as_u64().unwrap(), window[1].as_u64().unwrap()),
            "{}",
            ctx("column_window")
        );
        let shift: Vec<i64> = g["pixel_shift_by_row"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_i64().unwrap())
            .collect();
        assert_eq!(m.pixel_shift_by_row, shift, "{}", ctx("pixel_shift_by_row"));
        assert_eq!(
            m.udp_profile_lidar.name(),
            g["udp_profile_lidar"].as_str().unwrap(),
            "{}",
            ctx("udp_profile_lidar")
        );
        assert_eq!(
            m.udp_profile_lidar.returns() as u64,
            g["num_returns"].as_u64().unwrap(),
            "{}",
            ctx("num_returns")
        );
        assert_eq!(
            u64::from(m.fps),
            g["fps"].as_u64().unwrap(),
            "{}",
            ctx("fps")
        );
        assert_eq!(
            Some(m.lidar_mode.as_str()),
            g["lidar_mode"]
                .as_str()
                .map(|s| s.trim_start_matches("MODE_")),
            "{}",
            ctx("lidar_mode")
        );
        assert!(
            close(&m.beam_altitude_angles, &f64s(&g["beam_altitude_angles"])),
            "{}",
            ctx("beam_altitude_angles")
        );
        assert!(
            close(&m.beam_azimuth_angles, &f64s(&g["beam_azimuth_angles"])),
            "{}",
            ctx("beam_azimuth_angles")
        );
        assert!(
            close(
                &[m.lidar_origin_to_beam_origin_mm],
                &[g["lidar_origin_to_beam_origin_mm"].as_f64().unwrap()]
            ),
            "{}",
            ctx("origin")
        );
        let row_major =
            |mat: &nalgebra::Matrix4<f64>| mat.transpose().iter().copied().collect::<Vec<f64>>();
        assert!(
            close(
                &row_major(&m.beam_to_lidar_transform),
                &f64s(&g["beam_to_lidar_transform"])
            ),
            "{}",
            ctx("beam_to_lidar_transform")
        );
        assert!(
            close(
                &row_major(&m.lidar_to_sensor_transform),
                &f64s(&g["lidar_to_sensor_transform"])
            ),
            "{}",
            ctx("lidar_to_sensor_transform")
        );
        assert_eq!(
            m.prod_line,
            g["prod_line"].as_str().unwrap(),
            "{}",
            ctx("prod_line")
        );
        assert_eq!(m.fw_rev, g["fw_rev"].as_str().unwrap(), "{}", ctx("fw_rev"));
    }
}

#[test]
fn the_paper_sensor_is_read_as_expected() {
    let m =
        OusterMetadata::read(&fixtures().join("OS-0-128_v3.0.1_1024x10_from_osf.json")).unwrap();
    assert_eq!(m.prod_line, "OS-0-128");
    assert_eq!((m.columns_per_frame, m.pixels_per_column), (1024, 128));
    assert_eq!(m.udp_profile_lidar, UdpProfile::Rng19Rfl8Sig16Nir16);
}

#[test]
fn bad_metadata_names_the_file_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("not json", "not valid JSON"),
        ("[1, 2]", "expected a JSON object"),
        ("{\"lidar_mode\": \"1024x10\"}", "beam_altitude_angles"),
        ("{\"beam_altitude_angles\": [1, \"x\"], \"beam_azimuth_angles\": [0, 0], \"lidar_mode\": \"1024x10\"}", "finite numbers"),
        ("{\"beam_altitude_angles\": [1, 2], \"beam_azimuth_angles\": [0], \"lidar_mode\": \"1024x10\"}", "beam_azimuth_angles` has 1 entries"),
        ("{\"beam_altitude_angles\": [1, 2], \"beam_azimuth_angles\": [0, 0]}", "lidar_mode"),
        ("{\"beam_intrinsics\": {\"beam_altitude_angles\": [1], \"beam_azimuth_angles\": [0]}}", "lidar_data_format` is missing"),
    ];
    for (i, (text, expected)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("m{i}.json"));
        std::fs::write(&path, text).unwrap();
        let err = OusterMetadata::read(&path).unwrap_err().to_string();
        assert!(
            err.contains(&format!("m{i}.json")) && err.contains(expected),
            "{text}: {err}"
        );
    }
}
