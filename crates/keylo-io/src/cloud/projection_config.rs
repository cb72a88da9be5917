//! `[source.projection]`: the grid unorganised clouds are projected onto.

use serde::{Deserialize, Serialize};

/// Where a point's row comes from.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum RowSource {
    /// The ring field when the cloud has one, else the elevation.
    #[default]
    Auto,
    /// The ring field (an error when the cloud has none).
    Ring,
    /// The elevation, binned against `altitudes_deg` or the field of view.
    Elevation,
}

/// Which beam ring 0 is.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum RingOrder {
    /// Decided from the first cloud: the ring whose points are higher is the top.
    #[default]
    Auto,
    /// Ring 0 is the top beam (Ouster).
    TopFirst,
    /// Ring 0 is the bottom beam (Velodyne).
    BottomFirst,
}

/// `[source.projection]`: how unorganised clouds become images.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ProjectionConfig {
    /// Image rows (beams). Ignored when `altitudes_deg` is given (its length is used).
    pub rows: usize,
    /// Image columns over one revolution.
    pub cols: usize,
    /// How a point's row is chosen: `auto` (ring when present, else elevation), `ring`, or
    /// `elevation`.
    pub row_from: RowSource,
    /// Beam table: the elevation of every beam, degrees, in any order. A point goes to the
    /// beam of nearest elevation. Empty: rows split `fov_down_deg..fov_up_deg` evenly.
    pub altitudes_deg: Vec<f64>,
    /// Elevation of the top row, degrees (used without a beam table).
    pub fov_up_deg: f64,
    /// Elevation of the bottom row, degrees (used without a beam table).
    pub fov_down_deg: f64,
    /// Whether ring 0 is the top beam (`top-first`, Ouster), the bottom beam
    /// (`bottom-first`, Velodyne), or decided from the data (`auto`).
    pub ring_order: RingOrder,
    /// Revolutions per second. When a cloud has no per-point time, columns are spread over
    /// one revolution by azimuth; 0 gives every column the cloud's time (no deskew).
    pub frame_rate_hz: f64,
}

impl Default for ProjectionConfig {
    /// KITTI's HDL-64E as RangeNet++ projects it: 64×1024, +3° to −25°.
    fn default() -> Self {
        Self {
            rows: 64,
            cols: 1024,
            row_from: RowSource::Auto,
            altitudes_deg: Vec::new(),
            fov_up_deg: 3.0,
            fov_down_deg: -25.0,
            ring_order: RingOrder::Auto,
            frame_rate_hz: 0.0,
        }
    }
}

impl ProjectionConfig {
    /// Checks the numbers; the error names the key.
    pub fn validate(&self) -> Result<(), String> {
        let rows = self.effective_rows();
        if rows == 0 || rows > 4096 {
            return Err(format!("projection.rows = {rows}; expected 1..=4096"));
        }
        if self.cols == 0 || self.cols > 65536 {
            return Err(format!(
                "projection.cols = {}; expected 1..=65536",
                self.cols
            ));
        }
        if self
            .altitudes_deg
            .iter()
            .any(|a| !a.is_finite() || a.abs() > 90.0)
        {
            return Err("projection.altitudes_deg: every entry must be within -90..90".into());
        }
        let fov_ok = self.fov_up_deg.is_finite()
            && self.fov_down_deg.is_finite()
            && self.fov_up_deg > self.fov_down_deg
            && self.fov_up_deg <= 90.0
            && self.fov_down_deg >= -90.0;
        if self.altitudes_deg.is_empty() && !fov_ok {
            return Err(format!(
                "projection: fov_up_deg = {} and fov_down_deg = {}; expected -90 <= down < up <= 90",
                self.fov_up_deg, self.fov_down_deg
            ));
        }
        if !(self.frame_rate_hz.is_finite() && self.frame_rate_hz >= 0.0) {
            return Err(format!(
                "projection.frame_rate_hz = {}; expected >= 0",
                self.frame_rate_hz
            ));
        }
        Ok(())
    }

    pub(crate) fn effective_rows(&self) -> usize {
        if self.altitudes_deg.is_empty() {
            self.rows
        } else {
            self.altitudes_deg.len()
        }
    }

    /// Elevation of every row, degrees, top row first.
    pub(crate) fn row_altitudes(&self) -> Vec<f64> {
        if self.altitudes_deg.is_empty() {
            let rows = self.rows;
            let step = if rows > 1 {
                (self.fov_up_deg - self.fov_down_deg) / (rows - 1) as f64
            } else {
                0.0
            };
            (0..rows)
                .map(|r| self.fov_up_deg - r as f64 * step)
                .collect()
        } else {
            let mut a = self.altitudes_deg.clone();
            a.sort_by(|x, y| y.total_cmp(x));
            a
        }
    }
}
