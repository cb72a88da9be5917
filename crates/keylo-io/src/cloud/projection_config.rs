//! `[source.projection]`: the grid unorganised clouds are projected onto.

use serde::{Deserialize, Serialize};

use super::CloudError;

pub use super::sensors::Sensor;

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
///
/// `sensor` gives the grid of a known LiDAR; `rows`, `cols`, `altitudes_deg`, `fov_up_deg`
/// and `fov_down_deg`, when set, override it.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ProjectionConfig {
    /// The sensor whose beams and resolution the grid follows: `hdl-64e` (KITTI; 64 × 2048),
    /// `hdl-32e`, `vlp-16`, `vlp-32c`, `os-32`, `os-64`, `os-128`, `generic` (64 × 1024 over
    /// +3°..−25°), or `auto` (the source's: `hdl-64e` for KITTI folders, else `generic`).
    pub sensor: Sensor,
    /// Image rows (beams); unset: the sensor's. Ignored when `altitudes_deg` is given.
    pub rows: Option<usize>,
    /// Image columns over one revolution; unset: the sensor's.
    pub cols: Option<usize>,
    /// How a point's row is chosen: `auto` (ring when present, else elevation), `ring`, or
    /// `elevation`.
    pub row_from: RowSource,
    /// Beam table: the elevation of every beam, degrees, in any order. A point goes to the
    /// beam of nearest elevation. Unset: the sensor's table, or `rows` split evenly over
    /// `fov_down_deg..fov_up_deg`; `[]`: always the even split.
    pub altitudes_deg: Option<Vec<f64>>,
    /// Elevation of the top row, degrees, without a beam table; unset: the sensor's.
    pub fov_up_deg: Option<f64>,
    /// Elevation of the bottom row, degrees, without a beam table; unset: the sensor's.
    pub fov_down_deg: Option<f64>,
    /// Whether ring 0 is the top beam (`top-first`, Ouster), the bottom beam
    /// (`bottom-first`, Velodyne), or decided from the data (`auto`).
    pub ring_order: RingOrder,
    /// Revolutions per second. When a cloud has no per-point time, points get the time of
    /// their azimuth over one revolution; 0 gives every point the cloud's time (no deskew).
    pub frame_rate_hz: f64,
}

/// A projection with every value decided ([`ProjectionConfig::resolve`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Sensor name for the frames' beams.
    pub model: String,
    pub rows: usize,
    pub cols: usize,
    /// Elevation of every row, degrees, top row first.
    pub altitudes_deg: Vec<f64>,
    pub row_from: RowSource,
    pub ring_order: RingOrder,
    pub frame_rate_hz: f64,
}

impl ProjectionConfig {
    /// The grid for a source whose `auto` sensor is `source_default`, checked; the error
    /// names the key.
    pub fn resolve(&self, source_default: Sensor) -> Result<Grid, CloudError> {
        let sensor = self.sensor.or(source_default).grid();
        let table = match &self.altitudes_deg {
            Some(t) => t.clone(),
            None if self.rows.is_none()
                && self.fov_up_deg.is_none()
                && self.fov_down_deg.is_none() =>
            {
                sensor.altitudes_deg.clone()
            }
            None => Vec::new(),
        };
        if table.iter().any(|a| !a.is_finite() || a.abs() > 90.0) {
            return Err(CloudError::Projection {
                key: "altitudes_deg",
                value: format!("{table:?}"),
                expected: "every entry within -90..90",
            });
        }
        let rows = if table.is_empty() {
            self.rows.unwrap_or(sensor.rows)
        } else {
            table.len()
        };
        if rows == 0 || rows > 4096 {
            return Err(CloudError::Projection {
                key: "rows",
                value: rows.to_string(),
                expected: "1..=4096",
            });
        }
        let cols = self.cols.unwrap_or(sensor.cols);
        if cols == 0 || cols > 65536 {
            return Err(CloudError::Projection {
                key: "cols",
                value: cols.to_string(),
                expected: "1..=65536",
            });
        }
        let altitudes_deg = if table.is_empty() {
            let (up, down) = (
                self.fov_up_deg.unwrap_or(sensor.fov_deg.0),
                self.fov_down_deg.unwrap_or(sensor.fov_deg.1),
            );
            let fov_ok =
                up.is_finite() && down.is_finite() && up > down && up <= 90.0 && down >= -90.0;
            if !fov_ok {
                return Err(CloudError::Projection {
                    key: "fov_up_deg/fov_down_deg",
                    value: format!("{up}/{down}"),
                    expected: "-90 <= fov_down_deg < fov_up_deg <= 90",
                });
            }
            even_altitudes(up, down, rows)
        } else {
            let mut a = table;
            a.sort_by(|x, y| y.total_cmp(x));
            a
        };
        if !(self.frame_rate_hz.is_finite() && self.frame_rate_hz >= 0.0) {
            return Err(CloudError::Projection {
                key: "frame_rate_hz",
                value: self.frame_rate_hz.to_string(),
                expected: ">= 0",
            });
        }
        Ok(Grid {
            model: sensor.model.to_string(),
            rows,
            cols,
            altitudes_deg,
            row_from: self.row_from,
            ring_order: self.ring_order,
            frame_rate_hz: self.frame_rate_hz,
        })
    }
}

/// `rows` elevations from `up` down to `down`, evenly spaced (degrees, top first).
pub(crate) fn even_altitudes(up: f64, down: f64, rows: usize) -> Vec<f64> {
    let step = if rows > 1 {
        (up - down) / (rows - 1) as f64
    } else {
        0.0
    };
    (0..rows).map(|r| up - r as f64 * step).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sensors_fill_what_the_keys_leave_unset() {
        let kitti = ProjectionConfig::default().resolve(Sensor::Hdl64e).unwrap();
        assert_eq!(
            (kitti.rows, kitti.cols, kitti.model.as_str()),
            (64, 2048, "HDL-64E")
        );
        assert_eq!(kitti.altitudes_deg[0], 3.0);
        let generic = ProjectionConfig::default()
            .resolve(Sensor::Generic)
            .unwrap();
        assert_eq!((generic.rows, generic.cols), (64, 1024));
        let vlp = ProjectionConfig {
            sensor: Sensor::Vlp16,
            cols: Some(900),
            ..ProjectionConfig::default()
        }
        .resolve(Sensor::Hdl64e)
        .unwrap();
        assert_eq!((vlp.rows, vlp.cols), (16, 900));
        assert_eq!(vlp.altitudes_deg[15], -15.0);
        // Setting rows drops the sensor's table for an even split.
        let even = ProjectionConfig {
            sensor: Sensor::Vlp32c,
            rows: Some(8),
            ..ProjectionConfig::default()
        }
        .resolve(Sensor::Generic)
        .unwrap();
        assert_eq!(
            (even.rows, even.altitudes_deg[0], even.altitudes_deg[7]),
            (8, 15.0, -25.0)
        );
    }

    #[test]
    fn bad_values_name_their_key() {
        let cases = [
            (
                ProjectionConfig {
                    cols: Some(0),
                    ..Default::default()
                },
                "projection.cols",
            ),
            (
                ProjectionConfig {
                    rows: Some(0),
                    ..Default::default()
                },
                "projection.rows",
            ),
            (
                ProjectionConfig {
                    fov_up_deg: Some(-30.0),
                    ..Default::default()
                },
                "fov_up_deg",
            ),
            (
                ProjectionConfig {
                    altitudes_deg: Some(vec![100.0]),
                    ..Default::default()
                },
                "altitudes_deg",
            ),
            (
                ProjectionConfig {
                    frame_rate_hz: -1.0,
                    ..Default::default()
                },
                "frame_rate_hz",
            ),
        ];
        for (c, key) in cases {
            let e = c.resolve(Sensor::Generic).unwrap_err();
            assert!(e.to_string().contains(key), "{e}");
        }
    }
}
