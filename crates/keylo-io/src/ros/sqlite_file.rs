//! ROS2 bags in sqlite3 storage (`.db3`, the default of ROS 2 Foxy and Humble), read with
//! `rusqlite` (SQLite compiled in) through a read-only connection.
//!
//! Read: `topics(id, name, type, serialization_format)` and `messages(id, topic_id, timestamp,
//! data)`; other tables and columns (QoS profiles, type hashes, message definitions, schema
//! version) are not needed, so the schemas of every rosbag2 release read alike.
//!
//! Order: [`MessageFile::select`] walks the messages table once for the keys (id, topic,
//! timestamp: SQLite reads them from the leaf pages, never the payloads' overflow pages), keeps
//! the selected topics' and sorts them by `(timestamp, id)` as `ORDER BY timestamp, id` would;
//! a message's data is then read by id when it is next. Memory holds 24 bytes per selected
//! message, not the payloads. A streamed `ORDER BY` would need the `timestamp_idx` index
//! (which not every writer makes) to avoid sorting every payload, and would return nothing
//! from a damaged table; the key walk stops at the first unreadable page and keeps what it
//! read before it.
//!
//! Damage: the connection sets `writable_schema` (it still writes nothing), which stops SQLite
//! from refusing a file shorter than its header says, so a copy cut short reads up to the cut
//! like the other formats; [`super::sqlite_header`] names the cut in the errors.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rusqlite::{Connection, OpenFlags, OptionalExtension};

use super::file::{BagFormat, ChannelInfo, MessageFile, StoredMessage};
use super::sqlite_header::cut_short;
use super::wire::Encoding;
use crate::IoError;

/// The tables a rosbag2 sqlite3 file has, with the columns keylo reads.
const TABLES: [(&str, &str); 2] = [
    ("topics", "id, name, type, serialization_format"),
    ("messages", "id, topic_id, timestamp, data"),
];

/// Where a message is, and when.
#[derive(Debug, Clone, Copy)]
struct Key {
    time: u64,
    id: i64,
    channel: u32,
}

/// An open sqlite3 bag.
pub(crate) struct SqliteFile {
    path: PathBuf,
    conn: Connection,
    channels: Vec<ChannelInfo>,
    time_range: Option<(u64, u64)>,
    /// Where the walk of the messages table on opening stopped, or the file's cut.
    damage: Option<String>,
    /// How the file is shorter than its header says.
    cut: Option<String>,
    /// The selected messages in `(timestamp, id)` order, and the next to read.
    queue: Vec<Key>,
    next: usize,
    /// Damage met by the last key walk, reported after the messages before it.
    deferred: Option<String>,
    /// An error ended the stream.
    ended: bool,
}

impl SqliteFile {
    /// Opens a `.db3` file, checks its tables, lists its topics and counts its messages.
    pub fn open(path: &Path) -> Result<Self, IoError> {
        let cut = cut_short(path).map_err(|e| IoError::io(path, e))?;
        let fail = |m: String| IoError::format(path, with_cut(m, cut.as_deref()));
        let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let conn = Connection::open_with_flags(path, flags)
            .map_err(|e| fail(format!("cannot open the sqlite3 bag: {e}")))?;
        conn.pragma_update(None, "writable_schema", true)
            .map_err(|e| fail(format!("cannot open the sqlite3 bag: {e}")))?;
        check_tables(&conn).map_err(fail)?;
        let mut channels = read_topics(&conn).map_err(fail)?;
        let mut counts: BTreeMap<u32, u64> = BTreeMap::new();
        let mut range: Option<(u64, u64)> = None;
        let walked = walk_keys(&conn, |k| {
            *counts.entry(k.channel).or_insert(0) += 1;
            let t = k.time;
            range = Some(range.map_or((t, t), |(a, b)| (a.min(t), b.max(t))));
        });
        for c in &mut channels {
            c.count = Some(counts.get(&c.id).copied().unwrap_or(0));
        }
        Ok(Self {
            path: path.to_path_buf(),
            conn,
            channels,
            time_range: range,
            damage: damage(walked, cut.as_deref()),
            cut,
            queue: Vec::new(),
            next: 0,
            deferred: None,
            ended: true,
        })
    }

    /// The payload of message `id`.
    fn data(&self, id: i64) -> Result<Vec<u8>, String> {
        let mut stmt = self
            .conn
            .prepare("SELECT data FROM messages WHERE id = ?1")
            .map_err(|e| e.to_string())?;
        stmt.query_row([id], |row| row.get::<_, Vec<u8>>(0))
            .optional()
            .map_err(|e| e.to_string())?
            .ok_or_else(|| "no longer in the messages table".to_string())
    }
}

/// `message`, then the file's cut when it has one.
fn with_cut(message: String, cut: Option<&str>) -> String {
    match cut {
        Some(c) => format!("{message}; {c}"),
        None => message,
    }
}

/// What stops a read: damage met by a key walk (with the cut), else the cut itself.
fn damage(walked: Option<String>, cut: Option<&str>) -> Option<String> {
    match walked {
        Some(w) => Some(with_cut(w, cut)),
        None => cut.map(str::to_string),
    }
}

/// Both tables exist and have the columns read; errors say what a rosbag2 file holds.
fn check_tables(conn: &Connection) -> Result<(), String> {
    let names: Vec<String> = conn
        .prepare("SELECT name FROM sqlite_master WHERE type = 'table'")
        .and_then(|mut s| s.query_map([], |r| r.get(0))?.collect())
        .map_err(|e| format!("not a readable sqlite3 database: {e}"))?;
    for (table, columns) in TABLES {
        let expected = format!("a ROS2 sqlite3 bag has table `{table}` with columns {columns}");
        if !names.iter().any(|n| n == table) {
            return Err(format!("no `{table}` table ({expected})"));
        }
        conn.prepare(&format!("SELECT {columns} FROM {table} LIMIT 0"))
            .map_err(|e| format!("table `{table}`: {e} ({expected})"))?;
    }
    Ok(())
}

/// Every topic, in id order (counts are filled in by the caller).
fn read_topics(conn: &Connection) -> Result<Vec<ChannelInfo>, String> {
    let fail = |e: rusqlite::Error| format!("table `topics` unreadable: {e}");
    let mut stmt = conn
        .prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id")
        .map_err(fail)?;
    let rows = stmt
        .query_map([], |r| {
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, String>(2)?,
                r.get::<_, String>(3)?,
            ))
        })
        .map_err(fail)?;
    let mut out = Vec::new();
    for row in rows {
        let (id, topic, msg_type, format) = row.map_err(fail)?;
        let id = u32::try_from(id)
            .map_err(|_| format!("table `topics`: topic id {id} is out of range"))?;
        out.push(ChannelInfo {
            id,
            topic,
            msg_type,
            encoding: Encoding::from_mcap(&format),
            encoding_name: format,
            count: None,
        });
    }
    Ok(out)
}

/// Calls `each` with the key of every message in table order; returns where an unreadable
/// row or page stopped the walk.
fn walk_keys(conn: &Connection, mut each: impl FnMut(Key)) -> Option<String> {
    let mut seen = 0u64;
    let result = (|| -> Result<(), String> {
        let mut stmt = conn
            .prepare("SELECT id, topic_id, timestamp FROM messages")
            .map_err(|e| e.to_string())?;
        let mut rows = stmt.query([]).map_err(|e| e.to_string())?;
        while let Some(row) = rows.next().map_err(|e| e.to_string())? {
            each(key(row)?);
            seen += 1;
        }
        Ok(())
    })();
    result
        .err()
        .map(|e| format!("the messages table is unreadable after {seen} messages: {e}"))
}

fn key(row: &rusqlite::Row<'_>) -> Result<Key, String> {
    let get = |i: usize| row.get::<_, i64>(i).map_err(|e| e.to_string());
    let id = get(0)?;
    let (topic, time) = (get(1)?, get(2)?);
    Ok(Key {
        id,
        channel: u32::try_from(topic)
            .map_err(|_| format!("message id {id}: topic id {topic} is out of range"))?,
        time: u64::try_from(time)
            .map_err(|_| format!("message id {id}: negative timestamp {time}"))?,
    })
}

impl MessageFile for SqliteFile {
    fn path(&self) -> &Path {
        &self.path
    }

    fn format(&self) -> BagFormat {
        BagFormat::Ros2Sqlite3
    }

    fn channels(&self) -> &[ChannelInfo] {
        &self.channels
    }

    fn time_range(&self) -> Option<(u64, u64)> {
        self.time_range
    }

    fn note(&self) -> Option<&str> {
        None
    }

    fn damage(&self) -> Option<&str> {
        self.damage.as_deref()
    }

    fn select(&mut self, channels: &[u32]) {
        let mut queue = Vec::new();
        let walked = walk_keys(&self.conn, |k| {
            if channels.contains(&k.channel) {
                queue.push(k);
            }
        });
        self.deferred = damage(walked, self.cut.as_deref());
        queue.sort_unstable_by_key(|k| (k.time, k.id));
        self.queue = queue;
        self.next = 0;
        self.ended = false;
    }

    fn next_message(&mut self) -> Option<Result<StoredMessage, IoError>> {
        if self.ended {
            return None;
        }
        let Some(&key) = self.queue.get(self.next) else {
            self.ended = true;
            let damage = self.deferred.take()?;
            return Some(Err(IoError::format(
                &self.path,
                format!("{damage} (the messages before it were read)"),
            )));
        };
        self.next += 1;
        match self.data(key.id) {
            Ok(data) => Some(Ok(StoredMessage {
                channel: key.channel,
                log_time: key.time,
                data,
            })),
            Err(e) => {
                self.ended = true;
                let message = format!("message id {}: {e}", key.id);
                Some(Err(IoError::format(
                    &self.path,
                    with_cut(message, self.cut.as_deref()),
                )))
            }
        }
    }
}

#[cfg(test)]
#[path = "sqlite_tests.rs"]
mod tests;
