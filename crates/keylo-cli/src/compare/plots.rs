//! Plots of a comparison (plotters; PNG through the bitmap backend and the `png` crate, and
//! SVG): trajectories from above against ground truth, APE over time, points per frame,
//! odometry rate per frame and resident memory per frame, one set per data.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::error::CompareError;

/// One line of a figure.
pub struct Line {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    /// Drawn thick and black (the ground truth).
    pub reference: bool,
}

/// One figure: named line series over a shared pair of axes.
pub struct Figure {
    pub file_stem: String,
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Line>,
}

const SIZE: (u32, u32) = (960, 640);

/// Writes `<dir>/<stem>.png` and `.svg`; returns their paths. A figure without points is
/// skipped (empty list).
pub fn write(dir: &Path, fig: &Figure) -> Result<Vec<PathBuf>, CompareError> {
    if fig.series.iter().all(|s| s.points.is_empty()) {
        return Ok(Vec::new());
    }
    crate::plot_out::write(dir, &fig.file_stem, SIZE, fig)
        .map_err(|(path, message)| CompareError::Plot { path, message })
}

fn bounds(fig: &Figure) -> ((f64, f64), (f64, f64)) {
    let pts = fig.series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in pts.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    let pad = |a: f64, b: f64| {
        let p = ((b - a) * 0.05).max(1e-3);
        (a - p, b + p)
    };
    (pad(x0, x1), pad(y0, y1))
}

impl crate::plot_out::Draw for Figure {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        draw(root, self)
    }
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, fig: &Figure) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let ((x0, x1), (y0, y1)) = bounds(fig);
    let mut chart = ChartBuilder::on(root)
        .caption(&fig.title, ("sans-serif", 26))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(fig.x_label.as_str())
        .y_desc(fig.y_label.as_str())
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .draw()
        .map_err(e)?;
    let mut colour = 0usize;
    for line in &fig.series {
        let style = if line.reference {
            BLACK.stroke_width(3)
        } else {
            colour += 1;
            crate::plot_out::COLOURS[(colour - 1) % crate::plot_out::COLOURS.len()].stroke_width(2)
        };
        let pts = line
            .points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite());
        chart
            .draw_series(LineSeries::new(pts, style))
            .map_err(e)?
            .label(line.name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(e)?;
    Ok(())
}
