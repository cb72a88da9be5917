//! What a recording holds: topics, types, counts, time span, and the layout of the first
//! message of every PointCloud2 topic (for `keylo info`).

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::file::{BagFormat, MessageFile};
use super::msgs::PointCloud2;
use super::topics::{topics, Topic, POINTCLOUD2};
use crate::IoError;

/// A recording's contents.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BagInfo {
    /// The file read (the `.mcap` or `.db3` inside a ROS2 bag folder).
    pub path: PathBuf,
    /// ROS1 bag, MCAP or ROS2 sqlite3 bag.
    pub format: BagFormat,
    /// First and last log (record) time, nanoseconds.
    pub start_ns: Option<u64>,
    /// Last log time, nanoseconds.
    pub end_ns: Option<u64>,
    /// `end - start`, seconds.
    pub duration_s: Option<f64>,
    /// How the file had to be read (no index or summary: scanned).
    pub note: Option<String>,
    /// Where a damaged file stops being readable.
    pub damage: Option<String>,
    /// Every topic, by name.
    pub topics: Vec<TopicInfo>,
}

/// One topic of a recording.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TopicInfo {
    /// Topic name.
    pub name: String,
    /// Message type as stored (`sensor_msgs/PointCloud2` or `sensor_msgs/msg/PointCloud2`).
    pub msg_type: String,
    /// Payload encoding as stored (`ros1`, `cdr`, …).
    pub encoding: String,
    /// Messages, when the file says.
    pub count: Option<u64>,
    /// PointCloud2 topics: the layout of the first message.
    pub cloud: Option<CloudLayout>,
    /// PointCloud2 topics: why the first message could not be read.
    pub cloud_error: Option<String>,
}

/// The layout of one PointCloud2 message.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CloudLayout {
    /// Header stamp, nanoseconds.
    pub stamp_ns: i64,
    /// Header frame id.
    pub frame_id: String,
    /// Rows (1: unorganised).
    pub height: u32,
    /// Points per row.
    pub width: u32,
    /// Bytes per point.
    pub point_step: u32,
    /// Bytes per row.
    pub row_step: u32,
    /// Byte order of the point data.
    pub is_bigendian: bool,
    /// True when the driver says every point is valid.
    pub is_dense: bool,
    /// The point layout.
    pub fields: Vec<FieldInfo>,
}

/// One PointField.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldInfo {
    /// Field name.
    pub name: String,
    /// Byte offset inside a point.
    pub offset: u32,
    /// `INT8` … `FLOAT64` (or `datatype N` for unknown codes).
    pub datatype: String,
    /// Elements (1 for scalars).
    pub count: u32,
}

/// Lists what the `.bag`, `.mcap`, `.db3` or ROS2 bag folder at `path` holds. Reads the index
/// (or summary, or the sqlite3 keys) and the first message of each PointCloud2 topic.
pub fn bag_info(path: &Path) -> Result<BagInfo, IoError> {
    let mut file = super::open_file(path, None)?;
    let format = file.format();
    let all = topics(file.channels());
    let range = file.time_range();
    let infos = all.iter().map(|t| topic_info(file.as_mut(), t)).collect();
    Ok(BagInfo {
        path: file.path().to_path_buf(),
        format,
        start_ns: range.map(|r| r.0),
        end_ns: range.map(|r| r.1),
        duration_s: range.map(|(a, b)| b.saturating_sub(a) as f64 * 1e-9),
        note: file.note().map(str::to_string),
        damage: file.damage().map(str::to_string),
        topics: infos,
    })
}

fn topic_info(file: &mut dyn MessageFile, t: &Topic) -> TopicInfo {
    let mut info = TopicInfo {
        name: t.name.clone(),
        msg_type: t.msg_type.clone(),
        encoding: t.encoding_name.clone(),
        count: t.count,
        cloud: None,
        cloud_error: None,
    };
    let Some(encoding) = t.encoding.filter(|_| t.is(POINTCLOUD2)) else {
        return info;
    };
    file.select(&t.ids);
    match file.next_message() {
        Some(Ok(m)) => match PointCloud2::decode(&m.data, encoding) {
            Ok(pc) => info.cloud = Some(layout(&pc)),
            Err(e) => info.cloud_error = Some(e.to_string()),
        },
        Some(Err(e)) => info.cloud_error = Some(e.to_string()),
        None => {}
    }
    info
}

fn layout(pc: &PointCloud2) -> CloudLayout {
    const NAMES: [&str; 8] = [
        "INT8", "UINT8", "INT16", "UINT16", "INT32", "UINT32", "FLOAT32", "FLOAT64",
    ];
    CloudLayout {
        stamp_ns: pc.header.stamp_ns,
        frame_id: pc.header.frame_id.to_string(),
        height: pc.height,
        width: pc.width,
        point_step: pc.point_step,
        row_step: pc.row_step,
        is_bigendian: pc.is_bigendian,
        is_dense: pc.is_dense,
        fields: pc
            .fields
            .iter()
            .map(|f| FieldInfo {
                name: f.name.to_string(),
                offset: f.offset,
                datatype: usize::from(f.datatype)
                    .checked_sub(1)
                    .and_then(|i| NAMES.get(i))
                    .map_or(format!("datatype {}", f.datatype), |n| n.to_string()),
                count: f.count,
            })
            .collect(),
    }
}

impl fmt::Display for BagInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} ({})", self.path.display(), self.format.kind())?;
        if let (Some(a), Some(b), Some(d)) = (self.start_ns, self.end_ns, self.duration_s) {
            writeln!(f, "  time: {a} .. {b} ns ({d:.3} s)")?;
        }
        for line in [&self.note, &self.damage].into_iter().flatten() {
            writeln!(f, "  note: {line}")?;
        }
        for t in &self.topics {
            let count = t.count.map_or("?".to_string(), |n| n.to_string());
            writeln!(
                f,
                "  {}  {}  [{}]  {count} messages",
                t.name, t.msg_type, t.encoding
            )?;
            if let Some(c) = &t.cloud {
                let fields: Vec<String> = c
                    .fields
                    .iter()
                    .map(|x| format!("{}@{}:{}", x.name, x.offset, x.datatype))
                    .collect();
                writeln!(
                    f,
                    "    {}x{} (height x width), point_step {}, {}: {}",
                    c.height,
                    c.width,
                    c.point_step,
                    if c.is_bigendian {
                        "big-endian"
                    } else {
                        "little-endian"
                    },
                    fields.join(" ")
                )?;
            }
            if let Some(e) = &t.cloud_error {
                writeln!(f, "    first message unreadable: {e}")?;
            }
        }
        Ok(())
    }
}
