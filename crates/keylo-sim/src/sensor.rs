//! Ouster-like sensor intrinsics and the column/azimuth convention.
//!
//! Frames are produced **destaggered** with zero beam azimuth offsets: every pixel of a column
//! shares the column's azimuth and firing time.
//!
//! * Sensor frame: x forward, y left, z up (Ouster "sensor frame").
//! * Row 0 is the top beam; elevations are uniformly spaced from `+fov/2` down to `-fov/2`.
//! * Column `c` of `W` fires at `t0 + c/W · period` and looks at azimuth
//!   `φ(c) = π − 2π·c/W` (counter-clockwise from +x, wrapped to (−π, π]). This is ouster-sdk's
//!   `2π(1 − c/W)` encoder azimuth expressed in the sensor frame (rotated 180° about z from the
//!   lidar frame): column 0 looks backward (−x), `W/4` left (+y), `W/2` forward (+x), `3W/4`
//!   right (−y). The image reads like a panorama seen from the sensor, forward in the middle.

use std::f64::consts::PI;
use std::sync::Arc;

use keylo_core::BeamGeometry;
use nalgebra::Vector3;

use crate::SensorKind;

/// Minimum range, metres: closer returns are invalid.
pub const MIN_RANGE_M: f64 = 0.3;
/// Revolutions per second.
pub const FRAME_RATE_HZ: f64 = 10.0;

/// Intrinsics of the simulated sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorModel {
    /// Model name, e.g. `OS0-128`.
    pub model: &'static str,
    /// Number of beams (rows).
    pub rows: usize,
    /// Columns per revolution.
    pub cols: usize,
    /// Vertical field of view, degrees (symmetric about the horizon).
    pub vertical_fov_deg: f64,
    /// Maximum range, metres.
    pub max_range_m: f64,
    /// Minimum range, metres.
    pub min_range_m: f64,
    /// Revolutions per second.
    pub frame_rate_hz: f64,
}

impl SensorModel {
    /// The model of `kind` with `cols` columns and an optional max-range override.
    pub fn new(kind: SensorKind, cols: usize, max_range_m: Option<f64>) -> Self {
        let (model, rows, fov, max) = match kind {
            SensorKind::Os0_128 => ("OS0-128", 128, 90.0, 75.0),
            SensorKind::Os1_64 => ("OS1-64", 64, 45.0, 120.0),
        };
        Self {
            model,
            rows,
            cols,
            vertical_fov_deg: fov,
            max_range_m: max_range_m.unwrap_or(max),
            min_range_m: MIN_RANGE_M,
            frame_rate_hz: FRAME_RATE_HZ,
        }
    }

    /// Duration of one revolution, seconds.
    pub fn period(&self) -> f64 {
        1.0 / self.frame_rate_hz
    }

    /// Elevation of beam `row`, degrees (row 0 = top).
    pub fn altitude_deg(&self, row: usize) -> f64 {
        let half = self.vertical_fov_deg / 2.0;
        if self.rows < 2 {
            return 0.0;
        }
        half - self.vertical_fov_deg * row as f64 / (self.rows - 1) as f64
    }

    /// Azimuth of column `col`, radians, counter-clockwise from +x, in (−π, π].
    pub fn azimuth_rad(&self, col: usize) -> f64 {
        let a = PI - 2.0 * PI * col as f64 / self.cols as f64;
        if a <= -PI {
            a + 2.0 * PI
        } else {
            a
        }
    }

    /// Firing time of column `col` relative to the frame start, seconds.
    pub fn column_offset(&self, col: usize) -> f64 {
        col as f64 / self.cols as f64 * self.period()
    }

    /// Unit direction of pixel `(row, col)` in the sensor frame.
    pub fn direction(&self, row: usize, col: usize) -> Vector3<f64> {
        let alt = self.altitude_deg(row).to_radians();
        let az = self.azimuth_rad(col);
        Vector3::new(alt.cos() * az.cos(), alt.cos() * az.sin(), alt.sin())
    }

    /// Per-row `(cos, sin)` of the elevation, row 0 first.
    pub fn altitude_table(&self) -> Vec<(f64, f64)> {
        (0..self.rows)
            .map(|r| {
                let a = self.altitude_deg(r).to_radians();
                (a.cos(), a.sin())
            })
            .collect()
    }

    /// The [`BeamGeometry`] of this sensor (zero beam azimuth offsets, zero beam origin offset).
    pub fn beam_geometry(&self) -> Arc<BeamGeometry> {
        Arc::new(BeamGeometry {
            model: self.model.to_string(),
            altitude_deg: (0..self.rows).map(|r| self.altitude_deg(r)).collect(),
            azimuth_deg: vec![0.0; self.rows],
            origin_to_beam_mm: 0.0,
            columns_per_frame: self.cols,
            frame_rate_hz: self.frame_rate_hz,
            column_lag_by_row: Vec::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn os0_beams_span_ninety_degrees_top_first() {
        let s = SensorModel::new(SensorKind::Os0_128, 1024, None);
        assert_eq!(s.rows, 128);
        assert!((s.altitude_deg(0) - 45.0).abs() < 1e-12);
        assert!((s.altitude_deg(127) + 45.0).abs() < 1e-12);
        assert_eq!(s.max_range_m, 75.0);
        let g = s.beam_geometry();
        assert_eq!(g.altitude_deg.len(), 128);
        assert_eq!(g.columns_per_frame, 1024);
    }

    #[test]
    fn os1_geometry_and_range_override() {
        let s = SensorModel::new(SensorKind::Os1_64, 512, Some(50.0));
        assert_eq!(s.rows, 64);
        assert!((s.altitude_deg(63) + 22.5).abs() < 1e-12);
        assert_eq!(s.max_range_m, 50.0);
    }

    #[test]
    fn column_convention_matches_ouster_sensor_frame() {
        let s = SensorModel::new(SensorKind::Os0_128, 1024, None);
        let mid = 64; // close to the horizon
        let back = s.direction(mid, 0);
        let left = s.direction(mid, 256);
        let fwd = s.direction(mid, 512);
        let right = s.direction(mid, 768);
        assert!(back.x < -0.99 && left.y > 0.99 && fwd.x > 0.99 && right.y < -0.99);
        assert!((s.column_offset(512) - 0.05).abs() < 1e-12);
        let a = s.azimuth_rad(0);
        assert!(a > 0.0 && (a - PI).abs() < 1e-12);
    }
}
