//! What ROS1 bags, mcap files and sqlite3 bags have in common for keylo: channels (topic, type,
//! encoding, message count) and a stream of stored messages in log-time order.

use std::path::{Path, PathBuf};

use super::wire::Encoding;
use crate::IoError;

/// The container formats keylo reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BagFormat {
    /// ROS1 bag (`#ROSBAG V2.0`).
    Ros1Bag,
    /// MCAP (ROS2 bags since Iron; also written by Foxglove tools).
    Mcap,
    /// ROS2 bag in sqlite3 storage (`.db3`; ROS2 bags up to Humble).
    Ros2Sqlite3,
}

impl BagFormat {
    /// The source kind reading this format.
    /// ROS2 bags of either storage are read by kind `mcap`.
    pub fn kind(self) -> &'static str {
        match self {
            Self::Ros1Bag => "ros1-bag",
            Self::Mcap | Self::Ros2Sqlite3 => "mcap",
        }
    }

    /// The format's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Ros1Bag => "ROS1 bag",
            Self::Mcap => "MCAP",
            Self::Ros2Sqlite3 => "ROS2 sqlite3 bag",
        }
    }
}

/// A ROS1 connection, an mcap channel or a sqlite3 bag's topic.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ChannelInfo {
    /// Connection or channel id.
    pub id: u32,
    pub topic: String,
    /// Message type as stored (`sensor_msgs/PointCloud2` or `sensor_msgs/msg/PointCloud2`).
    pub msg_type: String,
    /// Payload encoding; `None` for encodings keylo does not read.
    pub encoding: Option<Encoding>,
    /// The encoding's name as stored.
    pub encoding_name: String,
    /// Messages on the channel, when the file says.
    pub count: Option<u64>,
}

/// `pkg/msg/Name` → `pkg/Name` (ROS2 and ROS1 spellings compare equal).
pub(crate) fn normalise_type(t: &str) -> String {
    t.replacen("/msg/", "/", 1)
}

/// One message as stored.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct StoredMessage {
    pub channel: u32,
    /// Record (log) time, nanoseconds.
    pub log_time: u64,
    pub data: Vec<u8>,
}

/// A bag or mcap file opened for reading.
pub(crate) trait MessageFile: Send {
    /// The file read.
    fn path(&self) -> &Path;
    /// Its format.
    fn format(&self) -> BagFormat;
    /// Every channel, in id order.
    fn channels(&self) -> &[ChannelInfo];
    /// First and last log time, nanoseconds, when known.
    fn time_range(&self) -> Option<(u64, u64)>;
    /// How the file had to be read when it is damaged or unindexed.
    fn note(&self) -> Option<&str>;
    /// Damage found on opening (where a truncated or corrupt file stops being readable).
    fn damage(&self) -> Option<&str>;
    /// Restarts reading at the beginning, with only the messages of `channels`.
    fn select(&mut self, channels: &[u32]);
    /// The next selected message in log-time order; an `Err` ends the stream.
    fn next_message(&mut self) -> Option<Result<StoredMessage, IoError>>;
}

/// The file of `path` with its format: a `.bag`/`.mcap`/`.db3` file (told apart by magic
/// bytes), or a ROS2 bag folder holding one `.mcap` or `.db3` file.
pub(crate) fn resolve(path: &Path) -> Result<(PathBuf, BagFormat), IoError> {
    let file = if path.is_dir() {
        super::ros2_folder::storage_file(path)?
    } else {
        path.to_path_buf()
    };
    let mut head = [0u8; 16];
    let n = read_prefix(&file, &mut head)?;
    if head[..n].starts_with(b"#ROSBAG V2.0\n") {
        Ok((file, BagFormat::Ros1Bag))
    } else if head[..n].starts_with(b"\x89MCAP0\r\n") {
        Ok((file, BagFormat::Mcap))
    } else if head[..n].starts_with(b"#ROSBAG V") {
        Err(IoError::format(
            &file,
            "ROS1 bag of an old version: only bag format 2.0 is read (`rosbag fix` upgrades it)",
        ))
    } else if head[..n].starts_with(b"SQLite format 3\0") {
        Ok((file, BagFormat::Ros2Sqlite3))
    } else {
        Err(IoError::format(
            &file,
            "neither a ROS1 bag (#ROSBAG V2.0), an MCAP file (magic \\x89MCAP0) nor a ROS2 \
             sqlite3 bag (magic `SQLite format 3`)",
        ))
    }
}

fn read_prefix(path: &Path, buf: &mut [u8]) -> Result<usize, IoError> {
    use std::io::Read;
    let mut f = std::fs::File::open(path).map_err(|e| IoError::io(path, e))?;
    let mut n = 0;
    while n < buf.len() {
        match f.read(&mut buf[n..]).map_err(|e| IoError::io(path, e))? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn types_normalise_and_formats_are_told_by_magic() {
        assert_eq!(
            normalise_type("sensor_msgs/msg/PointCloud2"),
            "sensor_msgs/PointCloud2"
        );
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, bytes: &[u8]| {
            let p = dir.path().join(name);
            std::fs::write(&p, bytes).unwrap();
            p
        };
        let bag = write("a.bag", b"#ROSBAG V2.0\nrest");
        assert_eq!(resolve(&bag).unwrap().1, BagFormat::Ros1Bag);
        let mcap = write("b", b"\x89MCAP0\r\nrest");
        assert_eq!(resolve(&mcap).unwrap().1, BagFormat::Mcap);
        let old = write("c.bag", b"#ROSBAG V1.2\n");
        assert!(resolve(&old)
            .unwrap_err()
            .to_string()
            .contains("old version"));
        let db3 = write("d", b"SQLite format 3\0rest");
        assert_eq!(resolve(&db3).unwrap().1, BagFormat::Ros2Sqlite3);
        let junk = write("e.bag", b"hi");
        assert!(resolve(&junk).unwrap_err().to_string().contains("neither"));
    }

    #[test]
    fn ros2_folders_resolve_to_their_storage_file() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("metadata.yaml"), "x").unwrap();
        assert!(resolve(dir.path())
            .unwrap_err()
            .to_string()
            .contains("no .mcap or .db3"));
        std::fs::write(dir.path().join("a_0.db3"), b"SQLite format 3\0").unwrap();
        let (file, format) = resolve(dir.path()).unwrap();
        assert_eq!(
            (file.file_name().unwrap(), format),
            ("a_0.db3".as_ref(), BagFormat::Ros2Sqlite3)
        );
        std::fs::write(dir.path().join("a_0.mcap"), b"\x89MCAP0\r\n").unwrap();
        let (file, format) = resolve(dir.path()).unwrap();
        assert_eq!(
            (file.file_name().unwrap(), format),
            ("a_0.mcap".as_ref(), BagFormat::Mcap)
        );
        std::fs::write(dir.path().join("a_1.mcap"), b"").unwrap();
        assert!(resolve(dir.path())
            .unwrap_err()
            .to_string()
            .contains("split"));
    }
}
