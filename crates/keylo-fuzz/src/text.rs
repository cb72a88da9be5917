//! Text formats: the TOML pipeline config and TUM / KITTI trajectories.

use keylo_core::config::RawConfig;
use keylo_core::Registry;
use keylo_io::trajectory::{parse_kitti, parse_kitti_with_times, parse_trajectory, parse_tum};

use crate::parts;

thread_local! {
    /// Every backend that builds without OpenCV: sources (keylo-io), simulator (keylo-sim),
    /// registrars and downsamplers (keylo-registration). keylo-features' detectors and
    /// descriptors need OpenCV, so `[detector]`/`[descriptor]` kinds other than `none`
    /// resolve to "unknown kind" errors here.
    static REGISTRY: Registry = {
        let mut r = Registry::default();
        keylo_sim::register(&mut r);
        keylo_io::register(&mut r);
        keylo_registration::register(&mut r);
        r
    };
}

/// A pipeline config: parsed, then resolved against the registry (every default filled,
/// every key checked).
pub fn config_toml(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(raw) = RawConfig::parse("fuzz.toml", text) else {
        return;
    };
    let _ = keylo_plugin::host::referenced(&raw);
    let _ = keylo_plugin::host::search_path(&raw);
    REGISTRY.with(|r| {
        let _ = r.resolve(&raw);
    });
}

/// A TUM trajectory (and the same text format-detected).
pub fn trajectory_tum(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = parse_tum(text, "fuzz.tum");
    let _ = parse_trajectory(text, "fuzz.txt");
}

/// A KITTI pose file, alone and with a `times.txt` as the second part ([`parts::split`]).
pub fn trajectory_kitti(data: &[u8]) {
    let [poses, times] = parts::split::<2>(data);
    let Ok(text) = std::str::from_utf8(poses) else {
        return;
    };
    let _ = parse_kitti(text, "fuzz.txt");
    let times: Vec<f64> = String::from_utf8_lossy(times)
        .split_whitespace()
        .filter_map(|t| t.parse().ok())
        .collect();
    let _ = parse_kitti_with_times(text, "fuzz.txt", &times);
}
