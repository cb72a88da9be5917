//! Damaged copies of the sqlite3 fixture (`tests/fixtures/ros/ouster_ros2_db3/`): cut short,
//! header or pages overwritten, tables missing, files missing. The messages before the damage
//! are read, then one error names the file and what is wrong; never a panic.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_mentions, read_until_error};
use keylo_core::BuildContext;
use keylo_io::ros::{bag_info, BagFormat, BagSource, BagSourceConfig};

fn fixture_bytes() -> Vec<u8> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ros");
    std::fs::read(dir.join("ouster_ros2_db3/ouster_ros2_db3.db3")).unwrap()
}

/// Writes `bytes` as `x.db3` in a fresh folder.
fn write(bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    common::temp_file("x.db3", bytes)
}

/// The fixture with `range` xor-ed.
fn flipped(range: std::ops::Range<usize>) -> Vec<u8> {
    let mut bytes = fixture_bytes();
    for b in &mut bytes[range] {
        *b ^= 0x5a;
    }
    bytes
}

/// Reads `topic` (projected to 32 x 1024 when unorganised): the frames read, then the error
/// (of opening or of reading), if any.
fn read(path: &Path, topic: &str) -> (usize, Option<String>) {
    let mut config = BagSourceConfig {
        path: path.display().to_string(),
        topic: topic.into(),
        ..BagSourceConfig::default()
    };
    config.projection.rows = Some(32);
    config.projection.cols = Some(1024);
    match BagSource::open(&config, &BuildContext::default(), BagFormat::Mcap) {
        Ok(mut source) => read_until_error(&mut source),
        Err(e) => (0, Some(e.to_string())),
    }
}

#[test]
fn a_copy_cut_short_reads_up_to_the_cut() {
    let bytes = fixture_bytes();
    // The last two pages hold the last /cloud_unorganised message.
    let (_d, path) = write(&bytes[..bytes.len() - 8192]);
    let (ok, err) = read(&path, "/cloud_unorganised");
    assert_eq!(ok, 2);
    assert_mentions(
        &err.unwrap(),
        &[
            "x.db3",
            "the file is cut short",
            "declares 527 pages of 4096 bytes",
            "the messages before it were read",
        ],
    );
    let info = bag_info(&path).unwrap();
    assert_eq!(info.topics.len(), 4);
    assert_mentions(&info.damage.unwrap(), &["after 5 messages", "cut short"]);
    // Cut before the messages: opening says so.
    let (_d, path) = write(&bytes[..4096]);
    let (ok, err) = read(&path, "/cloud_unorganised");
    assert_eq!(ok, 0);
    assert_mentions(&err.unwrap(), &["x.db3", "table `topics`", "cut short"]);
}

#[test]
fn cut_anywhere_never_panics_and_errors_name_the_file() {
    let bytes = fixture_bytes();
    let cuts = (0..bytes.len())
        .step_by(37_813)
        .chain([1, 17, 99, 100, 4095, bytes.len() - 1]);
    for cut in cuts {
        let (_d, path) = write(&bytes[..cut]);
        if let Err(e) = bag_info(&path) {
            assert_mentions(&e.to_string(), &["x.db3"]);
        }
        for topic in ["/ouster/points", "/cloud_unorganised"] {
            let (_, err) = read(&path, topic);
            assert!(cut == bytes.len() || err.is_some(), "cut {cut}: no error");
            assert_mentions(&err.unwrap_or_default(), &["x.db3"]);
        }
    }
}

#[test]
fn overwritten_header_bytes_are_an_error_naming_the_file() {
    let (_d, path) = write(&flipped(16..100));
    let (ok, err) = read(&path, "/cloud_unorganised");
    assert_eq!(ok, 0);
    assert_mentions(&err.unwrap(), &["x.db3", "not a readable sqlite3 database"]);
    let (_d, path) = write(&flipped(0..16));
    let e = bag_info(&path).err().unwrap().to_string();
    assert_mentions(&e, &["x.db3", "nor a ROS2 sqlite3 bag"]);
}

#[test]
fn overwritten_pages_end_the_stream_after_the_messages_before_them() {
    let len = fixture_bytes().len();
    let (_d, path) = write(&flipped(len - 8192..len));
    let (ok, err) = read(&path, "/cloud_unorganised");
    assert_eq!(ok, 2);
    assert_mentions(
        &err.unwrap(),
        &["x.db3", "unreadable after 5 messages", "malformed"],
    );
    // Garbage at many places: frames or an error naming the file, never a panic.
    let mut seed = 0x2545_f491_u64;
    for _ in 0..40 {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let at = (seed >> 33) as usize % (len - 256);
        let (_d, path) = write(&flipped(at..at + 256));
        let _ = bag_info(&path);
        for topic in ["/ouster/points", "/cloud_unorganised"] {
            if let (_, Some(e)) = read(&path, topic) {
                assert_mentions(&e, &["x.db3"]);
            }
        }
    }
}

#[test]
fn missing_tables_and_files_are_named() {
    for (table, sql) in [
        ("messages", "DROP TABLE messages"),
        ("topics", "DROP TABLE topics"),
    ] {
        let (_d, path) = write(&fixture_bytes());
        rusqlite::Connection::open(&path)
            .unwrap()
            .execute_batch(sql)
            .unwrap();
        let (_, err) = read(&path, "/cloud_unorganised");
        let expected = format!("no `{table}` table");
        assert_mentions(&err.unwrap(), &["x.db3", &expected]);
        let e = bag_info(&path).err().unwrap().to_string();
        assert_mentions(&e, &["x.db3", &expected, "a ROS2 sqlite3 bag has table"]);
    }
    let dir = tempfile::tempdir().unwrap();
    let (_, err) = read(&dir.path().join("gone.db3"), "");
    assert_mentions(&err.unwrap(), &["gone.db3"]);
    std::fs::write(
        dir.path().join("metadata.yaml"),
        "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n",
    )
    .unwrap();
    let (_, err) = read(dir.path(), "");
    let folder = dir.path().display().to_string();
    assert_mentions(&err.unwrap(), &[&folder, "no .db3 file"]);
}
