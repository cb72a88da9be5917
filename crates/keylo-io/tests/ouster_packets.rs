//! Decoded (staggered) channels of the Ouster sample captures against ouster-sdk 1.0.1's
//! per-frame sums (`tests/fixtures/ouster/reference_stats_ouster_sdk.json`).

use std::path::{Path, PathBuf};

use keylo_io::ouster::{Batcher, OusterMetadata, XyzLut};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ouster")
}

/// The sample's folder: the repository's fixtures, else `../shared/data/ouster` (samples too
/// large to commit); `None` when neither has it.
fn locate(pcap: &str) -> Option<PathBuf> {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/ouster");
    [fixtures(), shared]
        .into_iter()
        .find(|d| d.join(pcap).is_file())
}

fn check_file(pcap: &str) {
    let Some(dir) = locate(pcap) else {
        eprintln!("skipped: {pcap} is neither in tests/fixtures/ouster nor ../shared/data/ouster");
        return;
    };
    let golden: Value = serde_json::from_str(
        &std::fs::read_to_string(fixtures().join("reference_stats_ouster_sdk.json")).unwrap(),
    )
    .unwrap();
    let g = &golden["files"][pcap];
    let meta = OusterMetadata::read(&fixtures().join(g["metadata"].as_str().unwrap())).unwrap();
    let lut = XyzLut::new(&meta);
    let mut batcher = Batcher::open(&dir.join(pcap), &meta, meta.udp_port_lidar).unwrap();
    let mut frames = Vec::new();
    while let Some(f) = batcher.next_frame() {
        frames.push(f.unwrap());
    }
    let expected = g["frames"].as_array().unwrap();
    assert_eq!(frames.len(), expected.len(), "{pcap}: frame count");
    for (b, e) in frames.iter().zip(expected) {
        let f = &b.frame;
        let sum = |v: &[u32]| v.iter().map(|x| u64::from(*x)).sum::<u64>();
        let ctx = format!("{pcap} frame {}", f.frame_id);
        assert_eq!(
            u64::from(f.frame_id),
            e["frame_id"].as_u64().unwrap(),
            "{ctx}"
        );
        assert_eq!(
            b.complete,
            e["complete"].as_bool().unwrap(),
            "{ctx}: complete"
        );
        let valid = f.range_mm.iter().filter(|r| **r != 0).count() as u64;
        assert_eq!(
            valid,
            e["valid_range_px"].as_u64().unwrap(),
            "{ctx}: valid pixels"
        );
        assert_eq!(
            sum(&f.range_mm),
            e["sum_range_mm"].as_u64().unwrap(),
            "{ctx}: range"
        );
        assert_eq!(
            sum(&f.signal),
            e["sum_signal"].as_u64().unwrap(),
            "{ctx}: signal"
        );
        assert_eq!(
            sum(&f.reflectivity),
            e["sum_reflectivity"].as_u64().unwrap(),
            "{ctx}: reflectivity"
        );
        assert_eq!(
            sum(&f.near_ir),
            e["sum_near_ir"].as_u64().unwrap(),
            "{ctx}: near-IR"
        );
        let mut xyz = [0.0f64; 3];
        for r in 0..f.rows {
            for c in 0..f.cols {
                if let Some(p) = lut.point(r, c, f.range_mm[c * f.rows + r]) {
                    (0..3).for_each(|k| xyz[k] += p[k]);
                }
            }
        }
        let expected_xyz: Vec<f64> = e["sum_xyz_valid_m"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        for k in 0..3 {
            // A sum over ~10⁵ points: 1e-9 relative is far below 1 mm per point.
            let tol = 1e-9 * expected_xyz[k].abs().max(1.0);
            assert!(
                (xyz[k] - expected_xyz[k]).abs() < tol,
                "{ctx}: xyz[{k}] {} vs {}",
                xyz[k],
                expected_xyz[k]
            );
        }
        let first = f.column_valid.iter().position(|v| *v).unwrap() as u64;
        let last = f.column_valid.iter().rposition(|v| *v).unwrap() as u64;
        assert_eq!(
            (first, last),
            (
                e["first_valid_column"].as_u64().unwrap(),
                e["last_valid_column"].as_u64().unwrap()
            ),
            "{ctx}: columns"
        );
    }
}

#[test]
fn rng19_profile_matches_ouster_sdk() {
    check_file("OS-0-128_v3.0.1_1024x10_from_osf.pcap");
}

#[test]
fn legacy_profile_matches_ouster_sdk() {
    check_file("OS-1-64_1024x10_fw20.pcap");
}

#[test]
fn dual_return_profile_matches_ouster_sdk() {
    check_file("OS-0-128_v3.2.0-rc7_2048x10_dual_from_osf.pcap");
}
