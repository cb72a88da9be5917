//! Fuzz targets for every keylo parser: one `fn(&[u8])` per input format, each calling the
//! real parser (through the same entry point the CLI uses) and ignoring its `Err`. A panic,
//! abort, runaway allocation or hang inside one of them is a bug in the parser.
//!
//! The functions are driven two ways:
//! - by cargo-fuzz (`fuzz/fuzz_targets/<name>.rs`, run with `scripts/fuzz.sh`);
//! - by `cargo test -p keylo-fuzz`, which replays every committed corpus file
//!   (`fuzz/corpus/<name>/`) and every regression input (`fuzz/regressions/<name>/`), so the
//!   ordinary test suite guards them without a fuzzer.
//!
//! Parsers that take a path get the input written to a per-thread scratch folder
//! ([`scratch`]); inputs of several files are split with [`parts`]. Targets and formats:
//! `docs/reliability.md`, section "Fuzzing".
//!
//! ```
//! for target in keylo_fuzz::TARGETS {
//!     (target.run)(b"not a valid file of any format");
//! }
//! ```

mod frames;
mod kitti;
mod ouster;
pub mod parts;
mod plugin;
mod points;
mod ros;
pub mod scratch;
mod text;

/// One fuzz target: its name (the cargo-fuzz target and corpus folder) and its function.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    pub name: &'static str,
    pub run: fn(&[u8]),
}

/// Every fuzz target, in the order `scripts/fuzz.sh` runs them.
pub const TARGETS: &[Target] = &[
    Target {
        name: "ouster_metadata",
        run: ouster::ouster_metadata,
    },
    Target {
        name: "ouster_pcap",
        run: ouster::ouster_pcap,
    },
    Target {
        name: "ros1_bag",
        run: ros::ros1_bag,
    },
    Target {
        name: "mcap",
        run: ros::mcap,
    },
    Target {
        name: "ros2_db3",
        run: ros::ros2_db3,
    },
    Target {
        name: "ros_messages",
        run: ros::ros_messages,
    },
    Target {
        name: "ply",
        run: points::ply,
    },
    Target {
        name: "pcd",
        run: points::pcd,
    },
    Target {
        name: "kitti_bin",
        run: kitti::kitti_bin,
    },
    Target {
        name: "kitti_folder",
        run: kitti::kitti_folder,
    },
    Target {
        name: "klf",
        run: frames::klf,
    },
    Target {
        name: "frames_folder",
        run: frames::frames_folder,
    },
    Target {
        name: "config_toml",
        run: text::config_toml,
    },
    Target {
        name: "trajectory_tum",
        run: text::trajectory_tum,
    },
    Target {
        name: "trajectory_kitti",
        run: text::trajectory_kitti,
    },
    Target {
        name: "plugin_table",
        run: plugin::plugin_table,
    },
];

/// The target called `name`.
pub fn target(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

/// Frames read from one source at most (inputs are small; this bounds the time per input).
const MAX_FRAMES: usize = 8;

/// Reads up to [`MAX_FRAMES`] frames of `source`, checking that each is self-consistent
/// (a frame whose buffers disagree with its grid would panic later in the pipeline).
fn drain(source: &mut dyn keylo_core::ImageSource) {
    let _ = source.info();
    let _ = source.details();
    for _ in 0..MAX_FRAMES {
        match source.next_frame() {
            Some(Ok(frame)) => check_frame(&frame),
            Some(Err(_)) | None => break,
        }
    }
    let _ = source.ground_truth();
}

/// The invariants every [`keylo_core::LidarFrame`] a source returns must hold.
fn check_frame(f: &keylo_core::LidarFrame) {
    let n = f.rows * f.cols;
    assert_eq!(f.column_times.len(), f.cols, "column_times");
    for (name, len) in [
        ("range", f.range.len()),
        ("signal", f.signal.len()),
        ("reflectivity", f.reflectivity.len()),
        ("near_ir", f.near_ir.len()),
        ("points", f.points.len()),
        ("valid", f.valid.len()),
    ] {
        assert_eq!(
            len, n,
            "{name} holds {len} values for {}x{}",
            f.rows, f.cols
        );
    }
    if let Some(t) = &f.pixel_times {
        assert_eq!(t.len(), n, "pixel_times");
    }
}
