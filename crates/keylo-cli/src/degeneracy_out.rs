//! The registrar's per-frame degeneracy analysis in a run's output: `degeneracy.csv` (one
//! line per analysed frame) and the `degeneracy` block of `summary.json`.

use std::path::Path;

use anyhow::{Context, Result};
use keylo::Degeneracy;
use serde::Serialize;

/// Header of `degeneracy.csv`: eigenvalues ascending (per residual, rotations scaled by the
/// RMS range), then the weakest direction `[tx ty tz rx ry rz]`.
pub const DEGENERACY_CSV_HEADER: &str = "frame,condition,weak,l1,l2,l3,l4,l5,l6,\
     weakest_tx,weakest_ty,weakest_tz,weakest_rx,weakest_ry,weakest_rz,length_scale_m,residuals";

/// Aggregate over a run, in `summary.json`.
#[derive(Debug, Default, Serialize)]
pub struct DegeneracySummary {
    pub frames_analysed: usize,
    /// Frames with at least one weak direction.
    pub frames_weak: usize,
    pub median_condition: f64,
    /// Largest finite condition number.
    pub max_condition: f64,
    /// Mean |component| of the weakest direction over the degenerate frames
    /// `[tx ty tz rx ry rz]`: which axis the geometry leaves open.
    pub mean_weakest_direction: [f64; 6],
}

/// One frame's analysis, with its frame index.
#[derive(Debug, Clone)]
pub struct DegeneracyRow {
    pub frame: u64,
    pub degeneracy: Degeneracy,
}

/// The summary of `rows`; `None` when no frame was analysed.
pub fn summarise(rows: &[DegeneracyRow]) -> Option<DegeneracySummary> {
    if rows.is_empty() {
        return None;
    }
    let mut conditions: Vec<f64> = rows.iter().map(|r| r.degeneracy.condition).collect();
    conditions.sort_by(f64::total_cmp);
    let degenerate: Vec<&Degeneracy> = rows
        .iter()
        .map(|r| &r.degeneracy)
        .filter(|d| d.is_degenerate())
        .collect();
    let mut mean = [0.0; 6];
    for d in &degenerate {
        for (m, v) in mean.iter_mut().zip(d.eigenvectors[0]) {
            *m += v.abs() / degenerate.len() as f64;
        }
    }
    Some(DegeneracySummary {
        frames_analysed: rows.len(),
        frames_weak: degenerate.len(),
        median_condition: conditions[conditions.len() / 2],
        max_condition: conditions
            .iter()
            .copied()
            .filter(|c| c.is_finite())
            .fold(0.0, f64::max),
        mean_weakest_direction: mean,
    })
}

/// Writes `degeneracy.csv` when some frame was analysed.
pub fn write(dir: &Path, rows: &[DegeneracyRow]) -> Result<()> {
    if rows.is_empty() {
        return Ok(());
    }
    let sci = |x: &f64| format!("{x:.6e}");
    let records = rows.iter().map(|r| {
        let d = &r.degeneracy;
        let mut fields = vec![r.frame.to_string(), sci(&d.condition), d.weak.to_string()];
        fields.extend(d.eigenvalues.iter().map(sci));
        fields.extend(d.eigenvectors[0].iter().map(sci));
        fields.push(format!("{:.3}", d.length_scale));
        fields.push(d.residuals.to_string());
        fields
    });
    let header: Vec<&str> = DEGENERACY_CSV_HEADER.split(',').collect();
    let text = keylo::io::csv_table::table(&header, records);
    let p = dir.join("degeneracy.csv");
    std::fs::write(&p, text).with_context(|| format!("writing {}", p.display()))
}
