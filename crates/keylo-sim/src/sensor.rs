//! Ouster-like sensor intrinsics and the column/azimuth convention.
//!
//! Frames are produced **destaggered**. By default the beams have zero azimuth offsets: every
//! pixel of a column shares the column's azimuth and firing time. A staggered sensor
//! ([`SensorModel::staggered`], the `ouster` appearance's OS0-128; [`crate::stagger`]) has a
//! real sensor's beam azimuth offsets and beam origins: pixel `(r, c)` is then the return of
//! column `c − shift(r)`, fired at that column's time.
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
    /// Staggered beams; `None`: every beam looks along its column's azimuth from the lidar
    /// origin.
    pub stagger: Option<Stagger>,
}

/// A staggered sensor's beams (see [`crate::stagger`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Stagger {
    /// Per beam, its azimuth offset, degrees, Ouster's convention (the beam looks at its
    /// column's azimuth minus this), row 0 first.
    pub azimuth_deg: Vec<f64>,
    /// Distance from the lidar origin to the beam origins, metres (they lie on the column's
    /// azimuth).
    pub origin_m: f64,
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
            stagger: None,
        }
    }

    /// This sensor with a real sensor's staggered beams, where one is at hand (OS0-128; other
    /// models are returned as they are).
    pub fn staggered(mut self) -> Self {
        if self.model == "OS0-128" && self.rows == crate::stagger::OS0_128_BEAM_AZIMUTH_DEG.len() {
            self.stagger = Some(Stagger {
                azimuth_deg: crate::stagger::OS0_128_BEAM_AZIMUTH_DEG.to_vec(),
                origin_m: crate::stagger::OS0_128_BEAM_ORIGIN_M,
            });
        }
        self
    }

    /// Per row, how many columns earlier than its destaggered column its pixel fired (the
    /// beam's azimuth offset in whole columns, as Ouster's `pixel_shift_by_row`, modulo the
    /// columns); empty for an unstaggered sensor.
    pub fn column_lags(&self) -> Vec<usize> {
        let Some(st) = &self.stagger else {
            return Vec::new();
        };
        let cols = self.cols.max(1);
        st.azimuth_deg
            .iter()
            .map(|a| (a * cols as f64 / 360.0).round() as i64)
            .map(|shift| shift.rem_euclid(cols as i64) as usize)
            .collect()
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

    /// Unit direction of pixel `(row, col)` in the sensor frame, for an unstaggered sensor.
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

    /// The [`BeamGeometry`] of this sensor (zero beam azimuth offsets and beam origin offset
    /// unless staggered).
    pub fn beam_geometry(&self) -> Arc<BeamGeometry> {
        let (azimuth_deg, origin_to_beam_mm) = match &self.stagger {
            Some(st) => (st.azimuth_deg.clone(), st.origin_m * 1e3),
            None => (vec![0.0; self.rows], 0.0),
        };
        Arc::new(BeamGeometry {
            model: self.model.to_string(),
            altitude_deg: (0..self.rows).map(|r| self.altitude_deg(r)).collect(),
            azimuth_deg,
            origin_to_beam_mm,
            columns_per_frame: self.cols,
            frame_rate_hz: self.frame_rate_hz,
            column_lag_by_row: self.column_lags(),
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

    #[test]
    fn a_staggered_os0_shifts_its_rows_as_the_real_sensor_does() {
        // `pixel_shift_by_row` of the sensor whose beam offsets these are, at 2048 columns
        // (OS-0-128_v3.2.0-rc7_2048x10_dual_from_osf.json).
        let real: [i64; 128] = [
            62, 20, -21, -61, 59, 19, -20, -58, 57, 19, -19, -57, 56, 18, -19, -55, 54, 18, -18,
            -54, 53, 17, -18, -53, 52, 17, -17, -51, 51, 17, -17, -51, 50, 16, -17, -50, 49, 16,
            -17, -49, 49, 16, -16, -49, 48, 16, -16, -48, 48, 16, -16, -48, 48, 16, -16, -48, 48,
            16, -16, -48, 48, 16, -16, -48, 47, 16, -16, -48, 48, 16, -16, -48, 48, 16, -16, -48,
            48, 16, -16, -48, 48, 16, -16, -49, 49, 16, -16, -49, 49, 17, -16, -50, 50, 17, -16,
            -50, 51, 17, -17, -51, 52, 18, -17, -52, 53, 18, -17, -53, 54, 18, -18, -54, 55, 19,
            -18, -56, 57, 20, -19, -58, 59, 20, -19, -60, 61, 21, -20, -62,
        ];
        let s = SensorModel::new(SensorKind::Os0_128, 2048, None).staggered();
        let lags = s.column_lags();
        let expected: Vec<usize> = real.iter().map(|v| v.rem_euclid(2048) as usize).collect();
        assert_eq!(lags, expected);
        let g = s.beam_geometry();
        assert_eq!(g.column_lag_by_row, lags);
        assert!((g.origin_to_beam_mm - 27.116).abs() < 1e-9);
        assert_eq!(g.azimuth_deg[0], 10.83);
        // No table for the OS1-64: it stays unstaggered.
        let os1 = SensorModel::new(SensorKind::Os1_64, 1024, None).staggered();
        assert!(os1.stagger.is_none() && os1.column_lags().is_empty());
    }
}
