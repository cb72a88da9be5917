//! keylo data sources and sinks.
//!
//! - [`frames`]: keylo's own frame-folder format (the organised grid with every channel),
//!   written by `keylo sim` and read back as source kind `frames`.
//! - [`kitti_bin`]: plain KITTI-style `.bin` frames (x y z intensity, float32) for other tools.
//! - [`trajectory`]: TUM and KITTI trajectory files (read and written; evaluation is
//!   `keylo-eval`, which reads no file).

pub mod cloud;
pub mod csv_table;
mod error;
pub mod export;
pub mod folder;
pub mod frames;
pub mod kitti;
pub mod kitti_bin;
pub mod ouster;
pub mod pcd;
pub mod ply;
pub mod point_files;
#[cfg(feature = "ros")]
pub mod ros;
pub mod select;
pub mod trajectory;

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

/// Registers the source kinds of this crate and their `--data` probes.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.sources.add::<frames::FramesSourceConfig>(
        "frames",
        "a keylo frame folder (keylo-frames.json + frames/*.klf), e.g. written by `keylo sim`",
        |c, ctx| Ok(Box::new(frames::FramesSource::open(&c, ctx)?)),
    );
    registry.add_source_probe("frames", frames::is_frames_dir);
    registry.sources.add::<ouster::OusterSourceConfig>(
        "ouster",
        "an Ouster pcap capture with its sensor metadata JSON (X.json beside X.pcap, or `meta`)",
        |c, ctx| Ok(Box::new(ouster::OusterSource::open(&c, ctx)?)),
    );
    registry.add_source_probe("ouster", ouster::is_pcap);
    registry.sources.add::<ouster::OusterUdpConfig>(
        "ouster-udp",
        "an Ouster sensor live: its lidar UDP packets on `lidar_port`, with its metadata JSON (`meta`)",
        |c, ctx| Ok(Box::new(ouster::OusterSource::open_udp(&c, ctx)?)),
    );
    registry.sources.add::<kitti::KittiSourceConfig>(
        "kitti",
        "a KITTI odometry folder (velodyne/*.bin, times.txt, calib.txt; poses as LiDAR ground truth)",
        |c, ctx| Ok(Box::new(kitti::KittiSource::open(&c, ctx)?)),
    );
    registry.add_source_probe("kitti", kitti::is_kitti_data);
    registry.sources.add::<point_files::PlySourceConfig>(
        "ply",
        "a folder of .ply point files (ascii or binary), one per frame",
        point_files::build_ply,
    );
    registry.add_source_probe("ply", point_files::is_ply_data);
    registry.sources.add::<point_files::PcdSourceConfig>(
        "pcd",
        "a folder of .pcd point files (ascii, binary or binary_compressed), one per frame",
        point_files::build_pcd,
    );
    registry.add_source_probe("pcd", point_files::is_pcd_data);
    #[cfg(feature = "ros")]
    register_ros(registry);
}

/// Registers `ros1-bag` and `mcap` (feature `ros`).
#[cfg(feature = "ros")]
fn register_ros(registry: &mut keylo_core::Registry) {
    registry.sources.add::<ros::BagSourceConfig>(
        "ros1-bag",
        "a ROS1 .bag: sensor_msgs/PointCloud2 clouds (organised or projected), optional sensor_msgs/Image channels",
        |c, ctx| Ok(Box::new(ros::BagSource::open(&c, ctx, ros::BagFormat::Ros1Bag)?)),
    );
    registry.sources.add::<ros::BagSourceConfig>(
        "mcap",
        "an MCAP file, ROS2 sqlite3 .db3 file or ROS2 bag folder (storage mcap or sqlite3): sensor_msgs/PointCloud2 clouds (organised or projected), optional sensor_msgs/Image channels",
        |c, ctx| Ok(Box::new(ros::BagSource::open(&c, ctx, ros::BagFormat::Mcap)?)),
    );
    registry.add_source_probe("ros1-bag", ros::is_ros1_bag);
    registry.add_source_probe("mcap", ros::is_mcap);
}
