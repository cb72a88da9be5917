//! keylo data sources and sinks.
//!
//! - [`frames`]: keylo's own frame-folder format (the organised grid with every channel),
//!   written by `keylo sim` and read back as source kind `frames`.
//! - [`kitti_bin`]: plain KITTI-style `.bin` frames (x y z intensity, float32) for other tools.

pub mod cloud;
mod error;
pub mod frames;
pub mod kitti_bin;
pub mod ouster;
pub mod ros;
pub mod select;

pub use error::IoError;

/// Removes the files of `dir` whose extension is `ext` (frames of an earlier export).
pub fn remove_files_with_extension(dir: &std::path::Path, ext: &str) -> Result<(), IoError> {
    let entries = std::fs::read_dir(dir).map_err(|e| IoError::io(dir, e))?;
    for path in entries.filter_map(Result::ok).map(|e| e.path()) {
        if path.is_file() && path.extension().is_some_and(|x| x == ext) {
            std::fs::remove_file(&path).map_err(|e| IoError::io(&path, e))?;
        }
    }
    Ok(())
}

/// Registers source kinds `frames`, `ros1-bag` and `mcap` and their `--data` probes.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.sources.add::<frames::FramesSourceConfig>(
        "frames",
        "a keylo frame folder (keylo-frames.json + frames/*.klf), e.g. written by `keylo sim`",
        |c, ctx| Ok(Box::new(frames::FramesSource::open(&c, ctx)?)),
    );
    registry.add_source_probe("frames", frames::is_frames_dir);
    registry.sources.add::<ros::BagSourceConfig>(
        "ros1-bag",
        "a ROS1 .bag: sensor_msgs/PointCloud2 clouds (organised or projected), optional sensor_msgs/Image channels",
        |c, ctx| Ok(Box::new(ros::BagSource::open(&c, ctx, ros::BagFormat::Ros1Bag)?)),
    );
    registry.sources.add::<ros::BagSourceConfig>(
        "mcap",
        "an MCAP file or ROS2 bag folder: sensor_msgs/PointCloud2 clouds (organised or projected), optional sensor_msgs/Image channels",
        |c, ctx| Ok(Box::new(ros::BagSource::open(&c, ctx, ros::BagFormat::Mcap)?)),
    );
    registry.add_source_probe("ros1-bag", ros::is_ros1_bag);
    registry.add_source_probe("mcap", ros::is_mcap);
}
