//! The sweep's results: per cell and combination, the mean of every metric, kept in a CSV
//! appended as cells finish and read back to resume.

use std::io::Write;
use std::path::Path;
use std::sync::Mutex;

use serde::Serialize;

use super::grid::INTERPOLATIONS;
use crate::spec::interpolation_name;
use crate::{KpEvalError, METRICS};

/// The mean of every metric for one combination in one cell.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct CellResult {
    pub interpolation: String,
    pub width: usize,
    pub height: usize,
    pub combo: String,
    pub images: usize,
    /// `(metric key, mean)`, in [`METRICS`] order; metrics without a value are absent.
    pub means: Vec<(String, f64)>,
}

impl CellResult {
    /// The mean of metric `key`.
    pub fn mean(&self, key: &str) -> Option<f64> {
        self.means.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
    }

    /// The CSV fields, in [`csv_header`] order.
    pub(super) fn record(&self) -> Vec<String> {
        let mut fields = vec![
            self.interpolation.clone(),
            self.width.to_string(),
            self.height.to_string(),
            self.combo.clone(),
            self.images.to_string(),
        ];
        for m in METRICS {
            fields.push(self.mean(m.key).map_or_else(String::new, |v| v.to_string()));
        }
        fields
    }

    /// A record read back; `None` for one cut short (a kill mid-write) or unreadable.
    fn from_record(f: &[String]) -> Option<Self> {
        if f.len() != 5 + METRICS.len() {
            return None;
        }
        let means = METRICS
            .iter()
            .zip(&f[5..])
            .filter_map(|(m, v)| v.parse::<f64>().ok().map(|v| (m.key.to_string(), v)))
            .collect();
        Some(Self {
            interpolation: f[0].clone(),
            width: f[1].parse().ok()?,
            height: f[2].parse().ok()?,
            combo: f[3].clone(),
            images: f[4].parse().ok()?,
            means,
        })
    }
}

/// The columns of the sweep CSV.
pub fn csv_header() -> Vec<String> {
    let mut h: Vec<String> = ["interpolation", "width", "height", "combo", "images"]
        .map(String::from)
        .to_vec();
    h.extend(METRICS.iter().map(|m| m.key.to_string()));
    h
}

/// Results found in an earlier sweep's CSV (a missing file: none). A file with another
/// header is refused rather than mixed with.
pub fn read_store(path: &Path) -> Result<Vec<CellResult>, KpEvalError> {
    if !path.exists() || std::fs::metadata(path).is_ok_and(|m| m.len() == 0) {
        return Ok(Vec::new());
    }
    let (header, records) = keylo_io::csv_table::read(path).map_err(|e| KpEvalError::Format {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    if header != csv_header() {
        return Err(KpEvalError::Format {
            path: path.to_path_buf(),
            message: "not a keylo sweep CSV of this version (header differs): \
                      use another --out or delete it"
                .into(),
        });
    }
    // A record cut short by a kill mid-write is ignored (that cell is run again).
    Ok(records
        .iter()
        .filter_map(|r| CellResult::from_record(r))
        .collect())
}

/// Results in cell order (interpolations in the paper's order, then width, height, and
/// combination name), the order of [`SweepResult::results`].
pub fn sort_results(results: &mut [CellResult]) {
    let order = |r: &CellResult| {
        let i = INTERPOLATIONS
            .iter()
            .position(|x| interpolation_name(*x) == r.interpolation)
            .unwrap_or(usize::MAX);
        (i, r.width, r.height, r.combo.clone())
    };
    results.sort_by_key(order);
}

/// The sweep CSV, opened to append (`fresh`: emptied, with its header).
pub(super) fn open_store(path: &Path, fresh: bool) -> Result<Mutex<std::fs::File>, KpEvalError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| KpEvalError::io(dir, e))?;
    }
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| KpEvalError::io(path, e))?;
    if fresh {
        f.set_len(0).map_err(|e| KpEvalError::io(path, e))?;
        f.write_all(keylo_io::csv_table::line(csv_header()).as_bytes())
            .map_err(|e| KpEvalError::io(path, e))?;
    }
    Ok(Mutex::new(f))
}
