use std::path::Path;

use keylo_core::BeamGeometry;
use serde::{Deserialize, Serialize};

use crate::IoError;

/// The `keylo-frames.json` manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Always `keylo-frames`.
    pub format: String,
    /// Format version (1).
    pub version: u32,
    pub rows: usize,
    pub cols: usize,
    /// Number of frame files.
    pub frames: usize,
    pub beams: BeamGeometry,
    /// Free text (e.g. the simulator command that wrote the folder).
    #[serde(default)]
    pub description: String,
}

impl Manifest {
    /// Reads and checks a manifest.
    pub fn read(path: &Path) -> Result<Self, IoError> {
        let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
        let m: Manifest = serde_json::from_str(&text)
            .map_err(|e| IoError::format(path, format!("invalid manifest: {e}")))?;
        if m.format != "keylo-frames" || m.version != 1 {
            return Err(IoError::format(
                path,
                format!(
                    "format `{}` version {}: expected `keylo-frames` version 1",
                    m.format, m.version
                ),
            ));
        }
        if m.beams.altitude_deg.len() != m.rows {
            return Err(IoError::format(
                path,
                format!(
                    "beams.altitude_deg has {} entries, expected rows = {}",
                    m.beams.altitude_deg.len(),
                    m.rows
                ),
            ));
        }
        let lags = &m.beams.column_lag_by_row;
        if !lags.is_empty() && (lags.len() != m.rows || lags.iter().any(|&l| l >= m.cols)) {
            return Err(IoError::format(
                path,
                format!(
                    "beams.column_lag_by_row has {} entries (largest {}), expected none or \
                     rows = {}, each below cols = {}",
                    lags.len(),
                    lags.iter().max().copied().unwrap_or(0),
                    m.rows,
                    m.cols
                ),
            ));
        }
        Ok(m)
    }
}
