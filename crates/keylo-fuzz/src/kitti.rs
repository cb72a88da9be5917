//! KITTI scans (`.bin`) and KITTI folders (scans, `times.txt`, `calib.txt`, poses).

use keylo_core::BuildContext;
use keylo_io::kitti::{KittiSource, KittiSourceConfig};
use keylo_io::kitti_bin::read_kitti_bin;

use crate::{parts, scratch};

/// One `.bin` scan (float32 x y z reflectance).
pub fn kitti_bin(data: &[u8]) {
    scratch::with_files(&[("scan.bin", data)], true, |dir| {
        let _ = read_kitti_bin(&dir.join("scan.bin"));
    });
}

/// A KITTI folder of four parts ([`parts::split`]): `velodyne/000000.bin`, `times.txt`,
/// `calib.txt` and `poses.txt` (an empty part is a missing file), read as source kind
/// `kitti`.
pub fn kitti_folder(data: &[u8]) {
    let [scan, times, calib, poses] = parts::split::<4>(data);
    let files = [
        ("velodyne/000000.bin", scan),
        ("times.txt", times),
        ("calib.txt", calib),
        ("poses.txt", poses),
    ];
    scratch::with_files(&files, false, |dir| {
        let config = KittiSourceConfig {
            path: ".".into(),
            poses: if poses.is_empty() {
                String::new()
            } else {
                "poses.txt".into()
            },
            ..KittiSourceConfig::default()
        };
        let ctx = BuildContext {
            base_dir: dir.to_path_buf(),
            ..Default::default()
        };
        if let Ok(mut source) = KittiSource::open(&config, &ctx) {
            crate::drain(&mut source);
        }
    });
}
