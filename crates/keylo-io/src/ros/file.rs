//! What ROS1 bags and mcap files have in common for keylo: channels (topic, type, encoding,
//! message count) and a stream of stored messages in log-time order.

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
}

impl BagFormat {
    /// The source kind reading this format.
    pub fn kind(self) -> &'static str {
        match self {
            Self::Ros1Bag => "ros1-bag",
            Self::Mcap => "mcap",
        }
    }
}

/// A ROS1 connection or an mcap channel.
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

/// The file of `path` with its format: a `.bag`/`.mcap` file (told apart by magic bytes), or a
/// ROS2 bag folder holding one `.mcap` file.
pub(crate) fn resolve(path: &Path) -> Result<(PathBuf, BagFormat), IoError> {
    let file = if path.is_dir() {
        ros2_folder_file(path)?
    } else {
        path.to_path_buf()
    };
    let mut head = [0u8; 13];
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
    } else if head[..n].starts_with(b"SQLite format 3") {
        Err(IoError::format(
            &file,
            "a ROS2 sqlite3 (.db3) bag: convert it to mcap (`ros2 bag convert`) to read it",
        ))
    } else {
        Err(IoError::format(
            &file,
            "neither a ROS1 bag (#ROSBAG V2.0) nor an MCAP file (magic \\x89MCAP0)",
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

/// The `.mcap` file of a ROS2 bag folder (`metadata.yaml` + one `.mcap`).
fn ros2_folder_file(dir: &Path) -> Result<PathBuf, IoError> {
    let entries = std::fs::read_dir(dir).map_err(|e| IoError::io(dir, e))?;
    let paths: Vec<PathBuf> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    let with_ext = |ext: &str| -> Vec<&PathBuf> {
        paths
            .iter()
            .filter(|p| p.extension().is_some_and(|x| x == ext))
            .collect()
    };
    match with_ext("mcap").as_slice() {
        [one] => Ok((*one).clone()),
        [] if !with_ext("db3").is_empty() => Err(IoError::format(
            dir,
            "a ROS2 sqlite3 (.db3) bag: convert it to mcap (`ros2 bag convert`) to read it",
        )),
        [] => Err(IoError::format(dir, "the folder holds no .mcap file")),
        many => Err(IoError::format(
            dir,
            format!(
                "the folder holds {} .mcap files (a split bag); give one file as the path",
                many.len()
            ),
        )),
    }
}

/// True for a ROS2 bag folder: `metadata.yaml` and exactly one `.mcap` file.
pub(crate) fn is_ros2_mcap_folder(dir: &Path) -> bool {
    dir.join("metadata.yaml").is_file()
        && std::fs::read_dir(dir).is_ok_and(|entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| e.path().extension().is_some_and(|x| x == "mcap"))
                .count()
                == 1
        })
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
        let db3 = write("d.db3", b"SQLite format 3\0");
        assert!(resolve(&db3).unwrap_err().to_string().contains("db3"));
        let junk = write("e.bag", b"hi");
        assert!(resolve(&junk).unwrap_err().to_string().contains("neither"));
    }

    #[test]
    fn ros2_folders() {
        let dir = tempfile::tempdir().unwrap();
        assert!(!is_ros2_mcap_folder(dir.path()));
        std::fs::write(dir.path().join("metadata.yaml"), "x").unwrap();
        assert!(resolve(dir.path())
            .unwrap_err()
            .to_string()
            .contains("no .mcap"));
        std::fs::write(dir.path().join("a_0.mcap"), b"\x89MCAP0\r\n").unwrap();
        assert!(is_ros2_mcap_folder(dir.path()));
        let (file, format) = resolve(dir.path()).unwrap();
        assert_eq!(
            (file.file_name().unwrap(), format),
            ("a_0.mcap".as_ref(), BagFormat::Mcap)
        );
        std::fs::write(dir.path().join("a_1.mcap"), b"").unwrap();
        assert!(!is_ros2_mcap_folder(dir.path()));
        assert!(resolve(dir.path())
            .unwrap_err()
            .to_string()
            .contains("split"));
    }
}
