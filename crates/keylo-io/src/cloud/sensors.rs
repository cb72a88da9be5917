//! Image grids of known spinning LiDARs, for clouds that arrive unorganised.
//!
//! Columns are close to the sensor's firings per revolution at 10 Hz, so that few points
//! share a pixel; rows are its beams (a ring field gives the row directly, else the
//! elevation is binned against the beam table).

use serde::{Deserialize, Serialize};

/// `projection.sensor`: whose beam layout and resolution the grid follows.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Sensor {
    /// The source's own: `hdl-64e` for KITTI folders, `generic` for the others.
    #[default]
    Auto,
    /// 64 × 1024 over +3°..−25°: RangeNet++'s KITTI grid (keylo's grid before the presets).
    Generic,
    /// Velodyne HDL-64E (KITTI): 64 rows over +3°..−25°, 2048 columns.
    #[serde(rename = "hdl-64e")]
    Hdl64e,
    /// Velodyne HDL-32E: 32 beams +10.67°..−30.67° (1.33° apart), 2048 columns.
    #[serde(rename = "hdl-32e")]
    Hdl32e,
    /// Velodyne VLP-16 (Puck): 16 beams +15°..−15° (2° apart), 1800 columns (0.2°).
    #[serde(rename = "vlp-16")]
    Vlp16,
    /// Velodyne VLP-32C (Ultra Puck): its 32 uneven beams +15°..−25°, 1800 columns.
    #[serde(rename = "vlp-32c")]
    Vlp32c,
    /// Ouster OS-x with 32 beams (ring field), 1024 columns.
    #[serde(rename = "os-32")]
    Os32,
    /// Ouster OS-x with 64 beams (ring field), 1024 columns.
    #[serde(rename = "os-64")]
    Os64,
    /// Ouster OS-x with 128 beams (ring field), 1024 columns.
    #[serde(rename = "os-128")]
    Os128,
}

/// The grid a sensor gives.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SensorGrid {
    /// Name for the frames' beam geometry.
    pub(crate) model: &'static str,
    pub(crate) rows: usize,
    pub(crate) cols: usize,
    /// Beam elevations, degrees, top first; empty: `rows` spread over `fov`.
    pub(crate) altitudes_deg: Vec<f64>,
    /// (up, down) degrees.
    pub(crate) fov_deg: (f64, f64),
}

/// The VLP-16's beams, degrees.
fn vlp16() -> Vec<f64> {
    (0..16).map(|i| 15.0 - 2.0 * f64::from(i)).collect()
}

/// The VLP-32C's beams (Velodyne's manual), degrees, top first.
const VLP32C_DEG: [f64; 32] = [
    15.0, 10.333, 7.0, 4.667, 3.333, 2.333, 1.667, 1.333, 1.0, 0.667, 0.333, 0.0, -0.333, -0.667,
    -1.0, -1.333, -1.667, -2.0, -2.333, -2.667, -3.0, -3.333, -3.667, -4.0, -4.667, -5.333, -6.148,
    -7.254, -8.843, -11.31, -15.639, -25.0,
];

impl Sensor {
    /// The sensor `Auto` stands for in a source whose own default is `source_default`.
    pub(crate) fn or(self, source_default: Sensor) -> Sensor {
        match self {
            Sensor::Auto => source_default,
            s => s,
        }
    }

    /// The grid of the sensor (`Auto` as `Generic`).
    pub(crate) fn grid(self) -> SensorGrid {
        let even = |model, rows, cols, up, down| SensorGrid {
            model,
            rows,
            cols,
            altitudes_deg: Vec::new(),
            fov_deg: (up, down),
        };
        match self {
            Sensor::Auto | Sensor::Generic => even("generic", 64, 1024, 3.0, -25.0),
            Sensor::Hdl64e => even("HDL-64E", 64, 2048, 3.0, -25.0),
            Sensor::Hdl32e => even("HDL-32E", 32, 2048, 10.67, -30.67),
            Sensor::Vlp16 => SensorGrid {
                altitudes_deg: vlp16(),
                ..even("VLP-16", 16, 1800, 15.0, -15.0)
            },
            Sensor::Vlp32c => SensorGrid {
                altitudes_deg: VLP32C_DEG.to_vec(),
                ..even("VLP-32C", 32, 1800, 15.0, -25.0)
            },
            Sensor::Os32 => even("OS-32", 32, 1024, 22.5, -22.5),
            Sensor::Os64 => even("OS-64", 64, 1024, 22.5, -22.5),
            Sensor::Os128 => even("OS-128", 128, 1024, 22.5, -22.5),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_match_their_row_counts_and_descend() {
        for s in [
            Sensor::Generic,
            Sensor::Hdl64e,
            Sensor::Hdl32e,
            Sensor::Vlp16,
            Sensor::Vlp32c,
            Sensor::Os32,
            Sensor::Os64,
            Sensor::Os128,
        ] {
            let g = s.grid();
            assert!(
                g.altitudes_deg.is_empty() || g.altitudes_deg.len() == g.rows,
                "{s:?}"
            );
            assert!(g.altitudes_deg.windows(2).all(|w| w[0] > w[1]), "{s:?}");
            assert!(g.fov_deg.0 > g.fov_deg.1);
        }
        assert_eq!(Sensor::Auto.or(Sensor::Hdl64e), Sensor::Hdl64e);
        assert_eq!(Sensor::Vlp16.or(Sensor::Hdl64e), Sensor::Vlp16);
    }
}
