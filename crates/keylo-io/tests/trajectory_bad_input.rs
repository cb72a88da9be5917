//! Malformed trajectory files give errors that name the file and the line.

use std::path::PathBuf;

use keylo_io::trajectory::TrajectoryError;
use keylo_io::trajectory::{read_kitti, read_trajectory, read_tum};

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn message(result: Result<keylo_core::Trajectory, TrajectoryError>) -> String {
    result.unwrap_err().to_string()
}

const GOOD_TUM: &str = "0.0 1 2 3 0 0 0 1\n";

#[test]
fn empty_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "empty.tum", "");
    let msg = message(read_trajectory(&path));
    assert_eq!(
        msg,
        format!(
            "{}: no poses (the file is empty or holds only comments)",
            path.display()
        )
    );
    let path = write(&dir, "comments.tum", "# nothing\n\n");
    assert!(message(read_tum(&path)).contains("comments.tum: no poses"));
}

#[test]
fn wrong_column_count_on_a_later_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        &dir,
        "gt.tum",
        &format!("# header\n{GOOD_TUM}{GOOD_TUM}\n0.2 1 2 3 0\n"),
    );
    let msg = message(read_trajectory(&path));
    assert!(
        msg.ends_with("gt.tum line 5: expected 8 numbers, found 5"),
        "{msg}"
    );
}

#[test]
fn unknown_column_count_on_first_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "odd.txt", "\n1 2 3 4 5 6 7 8 9 10\n");
    let msg = message(read_trajectory(&path));
    assert!(
        msg.ends_with("odd.txt line 2: expected 8 (TUM) or 12 (KITTI) numbers, found 10"),
        "{msg}"
    );
}

#[test]
fn kitti_line_with_missing_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        &dir,
        "poses.txt",
        "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0\n",
    );
    let msg = message(read_kitti(&path));
    assert!(
        msg.ends_with("poses.txt line 2: expected 12 numbers, found 8"),
        "{msg}"
    );
}

#[test]
fn nan_value() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "est.tum", &format!("{GOOD_TUM}0.1 NaN 2 3 0 0 0 1\n"));
    let msg = message(read_trajectory(&path));
    assert!(
        msg.ends_with("est.tum line 2, column 2: value 'NaN' is not finite"),
        "{msg}"
    );
}

#[test]
fn garbage_text() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "junk.tum", "hello this is not a trajectory at all\n");
    let msg = message(read_trajectory(&path));
    assert!(
        msg.ends_with("junk.tum line 1, column 1: 'hello' is not a number"),
        "{msg}"
    );
    let path = write(&dir, "junk2.tum", "lorem ipsum\n");
    let msg = message(read_trajectory(&path));
    assert!(
        msg.ends_with("junk2.tum line 1: expected 8 (TUM) or 12 (KITTI) numbers, found 2"),
        "{msg}"
    );
}

#[test]
fn zero_quaternion() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "q.tum", &format!("{GOOD_TUM}0.1 0 0 0 0 0 0 0\n"));
    let msg = message(read_trajectory(&path));
    assert!(msg.contains("q.tum line 2: quaternion"), "{msg}");
}

#[test]
fn missing_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("absent.tum");
    let err = read_trajectory(&path).unwrap_err();
    assert!(matches!(err, TrajectoryError::Read { .. }));
    assert!(err.to_string().contains("absent.tum: cannot read"));
}
