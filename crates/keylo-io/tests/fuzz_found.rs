//! Inputs found by fuzzing (`scripts/fuzz.sh`) that crashed, hung or exhausted memory before
//! their fix; each must now give an error or frames, quickly. The files are the replay set of
//! crates/keylo-fuzz (`fuzz/regressions/<target>/`).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use keylo_core::{BuildContext, ImageSource};
use keylo_io::ros::{bag_info, BagFormat, BagSource, BagSourceConfig};

fn regression(target: &str, name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/regressions")
        .join(target)
        .join(name)
}

/// Opens `path` as `format` and reads it to the end, within `limit`.
fn read_recording(path: &Path, format: BagFormat, limit: Duration) {
    let t0 = Instant::now();
    let config = BagSourceConfig {
        path: path.display().to_string(),
        ..BagSourceConfig::default()
    };
    let ctx = BuildContext {
        base_dir: ".".into(),
        ..Default::default()
    };
    if let Ok(mut source) = BagSource::open(&config, &ctx, format) {
        while let Some(Ok(_)) = source.next_frame() {}
    }
    assert!(
        t0.elapsed() < limit,
        "{} took {:?}",
        path.display(),
        t0.elapsed()
    );
}

/// The index declares ~2^64 messages on the cloud topic: opening listed every selected
/// index (hours, gigabytes); the count is now computed.
#[test]
fn a_huge_declared_message_count_opens_quickly() {
    let limit = Duration::from_secs(5);
    let bag = regression("ros1_bag", "huge_message_count");
    read_recording(&bag, BagFormat::Ros1Bag, limit);
    let mcap = regression("mcap", "huge_message_count");
    read_recording(&mcap, BagFormat::Mcap, limit);
}

/// A channel record whose string field claims gigabytes (found under AddressSanitizer, whose malloc
/// limit caught it; without a sanitizer the reservation is never touched, so RSS stayed low):
/// the mcap crate's parser reserved the claimed length before reading it. keylo now checks
/// every length inside a record first (`tests/mcap_alloc.rs` measures the allocations).
#[test]
fn a_huge_string_length_inside_a_record_is_an_error() {
    // The lengths are the sizes of the mallocs ASan refused.
    for (target, name, claim) in [
        ("mcap", "asan_huge_channel_string", 3_039_297_536u64),
        ("ros1_bag", "asan_mcap_huge_channel_string", 2_543_294_359),
    ] {
        let path = regression(target, name);
        let info = bag_info(&path).unwrap();
        let said = format!("{:?} {:?}", info.note, info.damage);
        let channel = said.contains("(opcode 0x04): `");
        let claims = said.contains(&format!("declares {claim} bytes"));
        assert!(channel && claims, "{said}");
        read_recording(&path, BagFormat::Mcap, Duration::from_secs(5));
    }
}

/// `"lidar_mode": "1024810"` (no data format) read as 1 024 810 columns: the XYZ table for
/// them took over 2 GB. Columns and rows are now bounded by what Ouster sensors have.
#[test]
fn a_lidar_mode_of_a_million_columns_is_an_error() {
    let path = regression("ouster_metadata", "lidar_mode_1024810");
    let text = std::fs::read_to_string(&path).unwrap();
    let err = keylo_io::ouster::OusterMetadata::parse(&path, &text)
        .unwrap_err()
        .to_string();
    assert!(err.contains("1024810 columns"), "{err}");
    assert!(err.contains("at most 4096"), "{err}");
    assert!(err.contains("lidar_mode_1024810"), "{err}");
}
