//! Destaggered Ouster frames against ouster-sdk 1.0.1, pixel by pixel
//! (`tests/fixtures/ouster/pixel_golden.json`, made by `make_pixel_golden.py` beside it):
//! identical destaggered channels (SHA-256 of the uint32 images), XYZ within 1 mm and pixel
//! firing times within 1 µs on a sample of every 13th pixel.

use std::path::{Path, PathBuf};

use keylo_core::LidarFrame;
use keylo_io::ouster::{Batcher, Destaggerer, OusterMetadata, Return};
use serde_json::Value;
use sha2::{Digest, Sha256};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ouster")
}

fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/ouster")
}

fn sha(values: impl Iterator<Item = u32>) -> String {
    let mut h = Sha256::new();
    for v in values {
        h.update(v.to_le_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

fn ints(v: &[f32]) -> impl Iterator<Item = u32> + '_ {
    v.iter().map(|x| *x as u32)
}

fn range_mm(f: &LidarFrame) -> impl Iterator<Item = u32> + '_ {
    f.range
        .iter()
        .map(|r| (f64::from(*r) * 1000.0).round() as u32)
}

fn f32_at(blob: &[u8], at: usize) -> f32 {
    f32::from_le_bytes([blob[at], blob[at + 1], blob[at + 2], blob[at + 3]])
}

fn check_channels(ctx: &str, f: &LidarFrame, g: &Value, suffix: &str) {
    let want = |k: &str| g[format!("{k}{suffix}")].as_str().map(str::to_string);
    assert_eq!(
        Some(sha(range_mm(f))),
        want("range"),
        "{ctx}: range{suffix}"
    );
    assert_eq!(
        Some(sha(ints(&f.reflectivity))),
        want("reflectivity"),
        "{ctx}: reflectivity{suffix}"
    );
    if let Some(s) = want("signal") {
        assert_eq!(sha(ints(&f.signal)), s, "{ctx}: signal{suffix}");
    }
    if suffix.is_empty() {
        assert_eq!(
            Some(sha(ints(&f.near_ir))),
            want("near_ir"),
            "{ctx}: near_ir"
        );
    }
}

fn check_xyz_and_times(ctx: &str, f: &LidarFrame, g: &Value, blob: &[u8], step: usize) {
    let (xyz_at, time_at) = (
        g["xyz_offset"].as_u64().unwrap() as usize,
        g["time_offset"].as_u64().unwrap() as usize,
    );
    let t0 = g["t0_ns"].as_u64().unwrap() as f64;
    assert!((f.timestamp * 1e9 - t0).abs() < 1e3, "{ctx}: frame time");
    let mut worst = 0.0f64;
    for (k, i) in (0..f.rows * f.cols).step_by(step).enumerate() {
        let want = [0, 1, 2].map(|a| f32_at(blob, xyz_at + 12 * k + 4 * a));
        if want == [0.0; 3] {
            assert!(!f.valid[i], "{ctx}: pixel {i} has no return in ouster-sdk");
            continue;
        }
        assert!(f.valid[i], "{ctx}: pixel {i} should be valid");
        let d = (0..3)
            .map(|a| (f64::from(f.points[i][a]) - f64::from(want[a])).abs())
            .fold(0.0, f64::max);
        worst = worst.max(d);
        let t = u32::from_le_bytes(blob[time_at + 4 * k..][..4].try_into().unwrap());
        let dt = ((f.pixel_time(i) - f.timestamp) * 1e9 - f64::from(t)).abs();
        assert!(dt < 1e3, "{ctx}: pixel {i} time off by {dt} ns");
    }
    assert!(worst < 1e-3, "{ctx}: XYZ differs by {worst} m");
}

#[test]
fn destaggered_frames_equal_ouster_sdk() {
    let golden: Value = serde_json::from_str(
        &std::fs::read_to_string(fixtures().join("pixel_golden.json")).unwrap(),
    )
    .unwrap();
    let blob = std::fs::read(fixtures().join("pixel_golden_xyz.bin")).unwrap();
    let step = golden["xyz_step"].as_u64().unwrap() as usize;
    let mut checked = 0;
    for (name, file) in golden["files"].as_object().unwrap() {
        let dir = if file["external"].as_bool().unwrap() {
            shared()
        } else {
            fixtures()
        };
        let pcap = dir.join(name);
        if !pcap.is_file() {
            eprintln!("skipped: {} is absent", pcap.display());
            continue;
        }
        let meta = OusterMetadata::read(&pcap.with_extension("json")).unwrap();
        let destagger = Destaggerer::new(&meta);
        let mut batcher = Batcher::open(&pcap, &meta, meta.udp_port_lidar).unwrap();
        let expected = file["frames"].as_array().unwrap();
        for (k, g) in expected.iter().enumerate() {
            let raw = batcher.next_frame().unwrap().unwrap().frame;
            let ctx = format!("{name} frame {}", raw.frame_id);
            assert_eq!(
                u64::from(raw.frame_id),
                g["frame_id"].as_u64().unwrap(),
                "{ctx}"
            );
            let f = destagger.frame(&raw, k as u64, Return::Strongest);
            assert_eq!(f.check_shape(), Ok(()), "{ctx}");
            check_channels(&ctx, &f, g, "");
            check_xyz_and_times(&ctx, &f, g, &blob, step);
            if g.get("range2").is_some() {
                let second = destagger.frame(&raw, k as u64, Return::Second);
                check_channels(&ctx, &second, g, "2");
            }
            checked += 1;
        }
        assert!(
            batcher.next_frame().is_none(),
            "{name}: more frames than ouster-sdk"
        );
    }
    assert!(checked >= 12, "only {checked} frames checked");
}
