//! ROS recordings: ROS1 bags (source kind `ros1-bag`), and MCAP files, ROS2 sqlite3 (`.db3`)
//! files or ROS2 bag folders of either storage (source kind `mcap`).
//!
//! `sensor_msgs/PointCloud2` messages become frames (organised clouds pixel for pixel,
//! unorganised ones through [`crate::cloud::Projector`]); `sensor_msgs/Image` topics may fill
//! the frame's channels. Messages are read lazily in log-time order: only the index (or
//! summary; for sqlite3 bags the message keys) is read up front, then one chunk (one sqlite3
//! message) at a time. [`bag_info`] lists what a recording holds. Topics, fields, units and
//! time rules: `docs/formats.md`.

mod bag;
mod beams;
mod config;
mod file;
mod framer;
mod image;
mod info;
mod mcap_chunk;
mod mcap_file;
mod mcap_record;
mod mcap_stream;
mod mcap_summary;
mod merge;
mod msgs;
mod pointcloud2;
mod ros2_folder;
mod source;
mod sqlite_file;
mod sqlite_header;
mod sync;
mod topics;
mod wire;

use std::path::Path;

pub use config::{BagSourceConfig, ImageTopics};
pub use file::BagFormat;
pub use framer::CloudFramer;
pub use info::{bag_info, BagInfo, CloudLayout, FieldInfo, TopicInfo};
pub use msgs::{decode_header, DecodeError, Header, Image, PointCloud2, PointField};
pub use pointcloud2::to_raw_cloud;
pub use source::BagSource;
pub use wire::Encoding;

use crate::IoError;

/// Opens a recording; with `expected`, a file of the other format is an error naming the
/// kind that reads it.
fn open_file(
    path: &Path,
    expected: Option<BagFormat>,
) -> Result<Box<dyn file::MessageFile>, IoError> {
    let (file, format) = file::resolve(path)?;
    if let Some(want) = expected.filter(|&w| w.kind() != format.kind()) {
        return Err(IoError::format(
            &file,
            format!(
                "this is a {} file, read by source kind `{}`, not `{}`",
                format.name(),
                format.kind(),
                want.kind()
            ),
        ));
    }
    Ok(match format {
        BagFormat::Ros1Bag => Box::new(bag::BagFile::open(&file)?),
        BagFormat::Mcap => Box::new(mcap_file::McapFile::open(&file)?),
        BagFormat::Ros2Sqlite3 => Box::new(sqlite_file::SqliteFile::open(&file)?),
    })
}

/// `--data` probe of kind `ros1-bag`: a `.bag` file.
pub fn is_ros1_bag(path: &Path) -> bool {
    path.is_file() && path.extension().is_some_and(|x| x == "bag")
}

/// `--data` probe of kind `mcap`: an `.mcap` or `.db3` file, or a ROS2 bag folder
/// (`metadata.yaml` and one `.mcap` or `.db3` file).
pub fn is_mcap(path: &Path) -> bool {
    if path.is_dir() {
        ros2_folder::is_bag_folder(path)
    } else {
        path.is_file() && path.extension().is_some_and(|x| x == "mcap" || x == "db3")
    }
}
