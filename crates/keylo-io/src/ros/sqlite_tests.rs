//! Small sqlite3 bags made here: the schema of ROS 2 Humble (no type hashes, no timestamp
//! index), messages stored out of time order, and broken tables.

use std::path::{Path, PathBuf};

use rusqlite::Connection;

use super::*;

/// rosbag2's sqlite3 schema as ROS 2 Humble writes it (schema version 3), without the index.
const HUMBLE: &str = "
    CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
    CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
        serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
    CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,
        timestamp INTEGER NOT NULL, data BLOB NOT NULL);
    INSERT INTO schema VALUES (3, 'humble');
    INSERT INTO topics VALUES (1, '/points', 'sensor_msgs/msg/PointCloud2', 'cdr', '');
    INSERT INTO topics VALUES (2, '/imu', 'sensor_msgs/msg/Imu', 'cdr', '');
    INSERT INTO topics VALUES (7, '/odd', 'x/msg/Y', 'cbor', '');
";

fn db(dir: &Path, sql: &str, messages: &[(i64, i64, &[u8])]) -> PathBuf {
    let path = dir.join("bag_0.db3");
    let conn = Connection::open(&path).unwrap();
    conn.execute_batch(sql).unwrap();
    for (topic, time, data) in messages {
        conn.execute(
            "INSERT INTO messages (topic_id, timestamp, data) VALUES (?1, ?2, ?3)",
            rusqlite::params![topic, time, data],
        )
        .unwrap();
    }
    path
}

/// A message read: channel, log time, payload.
type Read = (u32, u64, Vec<u8>);

fn drain(file: &mut SqliteFile) -> Vec<Result<Read, String>> {
    std::iter::from_fn(|| file.next_message())
        .map(|m| {
            m.map(|m| (m.channel, m.log_time, m.data))
                .map_err(|e| e.to_string())
        })
        .collect()
}

fn open_err(path: &Path) -> String {
    match SqliteFile::open(path) {
        Ok(_) => panic!("{} opened", path.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn humble_bags_list_topics_and_read_in_timestamp_then_id_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = db(
        dir.path(),
        HUMBLE,
        &[
            (1, 300, b"c"),
            (2, 100, b"i0"),
            (1, 100, b"a"),
            (1, 200, b"b"),
            (1, 100, b"a2"),
        ],
    );
    let mut file = SqliteFile::open(&path).unwrap();
    assert_eq!(file.format(), BagFormat::Ros2Sqlite3);
    assert_eq!(file.time_range(), Some((100, 300)));
    assert_eq!((file.note(), file.damage()), (None, None));
    let listed: Vec<_> = file
        .channels()
        .iter()
        .map(|c| (c.id, c.topic.as_str(), c.encoding, c.count))
        .collect();
    assert_eq!(
        listed,
        [
            (1, "/points", Some(Encoding::Cdr), Some(4)),
            (2, "/imu", Some(Encoding::Cdr), Some(1)),
            (7, "/odd", None, Some(0)),
        ]
    );
    assert!(drain(&mut file).is_empty(), "nothing before a selection");
    file.select(&[1]);
    let got: Vec<_> = drain(&mut file).into_iter().map(Result::unwrap).collect();
    let want: Vec<Read> = [(100, "a"), (100, "a2"), (200, "b"), (300, "c")]
        .iter()
        .map(|(t, d)| (1, *t, d.as_bytes().to_vec()))
        .collect();
    assert_eq!(got, want);
    // Selecting again restarts; two topics interleave by time, then by id (insertion order).
    file.select(&[1, 2]);
    let times: Vec<(u32, u64)> = drain(&mut file)
        .into_iter()
        .map(|m| m.map(|m| (m.0, m.1)).unwrap())
        .collect();
    assert_eq!(times, [(2, 100), (1, 100), (1, 100), (1, 200), (1, 300)]);
}

#[test]
fn bad_rows_stop_the_walk_after_the_messages_before_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = db(
        dir.path(),
        HUMBLE,
        &[(1, 5, b"a"), (1, -1, b"b"), (1, 7, b"c")],
    );
    let mut file = SqliteFile::open(&path).unwrap();
    let damage = file.damage().unwrap().to_string();
    assert!(
        damage.contains("after 1 messages") && damage.contains("negative timestamp -1"),
        "{damage}"
    );
    file.select(&[1]);
    let got = drain(&mut file);
    assert_eq!(got.len(), 2);
    assert_eq!(got[0].as_ref().unwrap().2, b"a");
    let err = got[1].as_ref().unwrap_err();
    assert!(
        err.contains("bag_0.db3") && err.contains("the messages before it were read"),
        "{err}"
    );
}

#[test]
fn an_unreadable_payload_ends_the_stream_naming_the_message() {
    let dir = tempfile::tempdir().unwrap();
    let sql = HUMBLE.replace("data BLOB NOT NULL", "data BLOB");
    let path = db(dir.path(), &sql, &[(1, 5, b"a")]);
    Connection::open(&path)
        .unwrap()
        .execute("INSERT INTO messages VALUES (9, 1, 6, NULL)", [])
        .unwrap();
    let mut file = SqliteFile::open(&path).unwrap();
    file.select(&[1]);
    let got = drain(&mut file);
    assert_eq!(got.len(), 2, "{got:?}");
    let err = got[1].as_ref().unwrap_err();
    assert!(
        err.contains("bag_0.db3") && err.contains("message id 9"),
        "{err}"
    );
}

#[test]
fn missing_tables_columns_and_files_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let path = db(dir.path(), &HUMBLE.replace("messages(", "msgs("), &[]);
    let e = open_err(&path);
    assert!(
        e.contains("bag_0.db3") && e.contains("no `messages` table"),
        "{e}"
    );
    std::fs::remove_file(&path).unwrap();
    let path = db(
        dir.path(),
        &HUMBLE.replace(", data BLOB", ", payload BLOB"),
        &[],
    );
    let e = open_err(&path);
    assert!(
        e.contains("table `messages`") && e.contains("data") && e.contains("columns"),
        "{e}"
    );
    std::fs::remove_file(&path).unwrap();
    assert!(open_err(&path).contains("bag_0.db3"));
    let mut junk = b"SQLite format 3\0".to_vec();
    junk.extend(std::iter::repeat_n(0xa5u8, 4000));
    std::fs::write(&path, junk).unwrap();
    let e = open_err(&path);
    assert!(
        e.contains("bag_0.db3") && e.contains("not a readable sqlite3 database"),
        "{e}"
    );
}
