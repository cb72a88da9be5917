//! keylo's frame-folder format, version 1. A folder holds:
//!
//! - `keylo-frames.json`: `{"format": "keylo-frames", "version": 1, "rows", "cols",
//!   "frames", "beams": {model, altitude_deg, azimuth_deg, origin_to_beam_mm,
//!   columns_per_frame, frame_rate_hz}, "description"}`;
//! - `frames/NNNNNN.klf`: one binary file per frame (layout in [`codec`]);
//! - optionally `gt.tum`: ground-truth poses, one per frame, stamped like the estimates.
//!
//! Full description: `docs/formats.md`.

pub mod codec;
mod manifest;
mod source;
mod writer;

pub use manifest::Manifest;
pub use source::{is_frames_dir, FramesSource, FramesSourceConfig};
pub use writer::FramesWriter;

/// Name of the manifest file.
pub const MANIFEST: &str = "keylo-frames.json";
/// Sub-folder of the frame files.
pub const FRAMES_DIR: &str = "frames";
