//! Per-frame plots of a run, from its `frames.csv`: points and odometry time per frame.

use std::path::Path;

use anyhow::{Context, Result};

use crate::compare::plots::{Figure, Line};

const SIZE: (u32, u32) = (960, 420);

/// SVG figures of `dir/frames.csv` (none when the run has no such file).
pub fn frame_plots(dir: &Path) -> Result<Vec<(String, String)>> {
    let path = dir.join("frames.csv");
    if !path.is_file() {
        return Ok(Vec::new());
    }
    let (header, rows) = keylo::io::csv_table::read(&path)?;
    let column = |name: &str| -> Option<Vec<(f64, f64)>> {
        let frame = header.iter().position(|h| h == "frame")?;
        let k = header.iter().position(|h| h == name)?;
        let points = rows
            .iter()
            .filter_map(|r| Some((r.get(frame)?.parse().ok()?, r.get(k)?.parse().ok()?)))
            .collect();
        Some(points)
    };
    let line = |column_name: &str, label: &str| {
        column(column_name).map(|points| Line {
            name: label.into(),
            points,
            reference: false,
        })
    };
    let figures = [
        Figure {
            file_stem: "points".into(),
            title: "Points per frame".into(),
            x_label: "frame".into(),
            y_label: "points".into(),
            series: [
                line("cloud_points", "given to the registrar"),
                line(
                    "registered_points",
                    "registered (after its own voxel filter)",
                ),
                line("keypoints", "keypoints"),
            ]
            .into_iter()
            .flatten()
            .collect(),
        },
        Figure {
            file_stem: "odometry_ms".into(),
            title: "Odometry time per frame".into(),
            x_label: "frame".into(),
            y_label: "ms".into(),
            series: line("odometry_ms", "odometry (all stages)")
                .into_iter()
                .collect(),
        },
    ];
    let mut out = Vec::new();
    for fig in figures
        .iter()
        .filter(|f| f.series.iter().any(|s| !s.points.is_empty()))
    {
        let svg = crate::plot_out::svg_string(SIZE, fig)
            .map_err(anyhow::Error::msg)
            .with_context(|| format!("plotting {} of {}", fig.title, path.display()))?;
        out.push((fig.title.clone(), svg));
    }
    Ok(out)
}
