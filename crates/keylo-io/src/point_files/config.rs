//! `[source] kind = "ply"` and `kind = "pcd"`: the parameters of a folder of point files.

use serde::{Deserialize, Serialize};

use crate::cloud::ProjectionConfig;
use crate::folder::fields::{FieldOptions, RangeUnit, TimeUnit};
use crate::select::FrameSelection;

/// A folder of `.ply` or `.pcd` files, one per frame (`kind = "ply"` / `kind = "pcd"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PointFilesConfig {
    /// The folder of point files (one per frame, read in natural order of their names), or a
    /// single file; relative to the config file.
    pub path: String,
    /// Index of the first file to read.
    pub start: usize,
    /// Read every `stride`-th file from `start` (1 = every file).
    pub stride: usize,
    /// Files to read at most; 0 = all.
    pub max_frames: usize,
    /// Frames per second. Frame times are `index / frame_rate_hz` unless every file name is a
    /// time stamp (`1698412345.123456.pcd`: seconds; an integer from 1e8 up: s, ms, µs or ns
    /// by magnitude).
    pub frame_rate_hz: f64,
    /// Unit of the per-point time field (`t`, `time` or `timestamp`): `auto`, `s`, `us` or
    /// `ns`. `auto` decides per file from the span of the times: up to 10 → s, up to 1e7 → µs,
    /// more → ns. Times above 1e6 s are an absolute clock: the frame time is then the earliest
    /// point time.
    pub time_unit: TimeUnit,
    /// Unit of the `range` field: `auto` (integer fields are millimetres, as Ouster publishes
    /// them; float fields metres), `m` or `mm`.
    pub range_unit: RangeUnit,
    /// `[source.projection]`: how unorganised clouds become images. Organised PCD files
    /// (HEIGHT > 1) keep their own grid.
    pub projection: ProjectionConfig,
}

/// Parameters of `kind = "ply"`.
pub type PlySourceConfig = PointFilesConfig;
/// Parameters of `kind = "pcd"`.
pub type PcdSourceConfig = PointFilesConfig;

impl Default for PointFilesConfig {
    fn default() -> Self {
        Self {
            path: String::new(),
            start: 0,
            stride: 1,
            max_frames: 0,
            frame_rate_hz: 10.0,
            time_unit: TimeUnit::Auto,
            range_unit: RangeUnit::Auto,
            projection: ProjectionConfig::default(),
        }
    }
}

impl PointFilesConfig {
    /// The frame selection; the error names the key.
    pub fn selection(&self) -> Result<FrameSelection, crate::select::SelectionError> {
        FrameSelection::new(self.start, self.stride, self.max_frames)
    }

    /// The unit settings.
    pub fn field_options(&self) -> FieldOptions {
        FieldOptions {
            time_unit: self.time_unit,
            range_unit: self.range_unit,
        }
    }
}

/// Checks `frame_rate_hz`; the error names the key.
pub(crate) fn check_frame_rate(frame_rate_hz: f64) -> Result<(), String> {
    if frame_rate_hz.is_finite() && frame_rate_hz > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "`source.frame_rate_hz` = {frame_rate_hz}; expected a positive number"
        ))
    }
}
