//! Figures of the keypoint study: a box plot per metric over the combinations (like the
//! paper's figures 1–6) and, for the sweep, a width × height heat map per interpolation and
//! metric.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::plot_out::{Draw, COLOURS};

/// One box of a box plot: a name and its five numbers.
pub struct BoxRow {
    pub name: String,
    pub min: f64,
    pub q1: f64,
    pub median: f64,
    pub q3: f64,
    pub max: f64,
}

/// Horizontal box plots (one row per combination) of one metric.
pub struct BoxPlot {
    pub title: String,
    pub x_label: String,
    pub rows: Vec<BoxRow>,
}

/// A heat map of mean values over a width × height grid.
pub struct HeatMap {
    pub title: String,
    pub widths: Vec<usize>,
    pub heights: Vec<usize>,
    /// `values[h][w]` (`None`: no value).
    pub values: Vec<Vec<Option<f64>>>,
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-6);
    (lo - pad, hi + pad)
}

impl Draw for BoxPlot {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let (x0, x1) = range(self.rows.iter().flat_map(|r| [r.min, r.max]));
        let n = self.rows.len();
        let names: Vec<String> = self.rows.iter().map(|r| r.name.clone()).collect();
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, ("sans-serif", 24))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(190)
            .build_cartesian_2d(x0..x1, -0.5..(n as f64 - 0.5))
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(self.x_label.as_str())
            .y_labels(n.max(1))
            .y_label_formatter(&|y| {
                let i = y.round();
                if (y - i).abs() < 1e-6 && i >= 0.0 {
                    names.get(i as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            })
            .disable_y_mesh()
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(e)?;
        for (i, r) in self.rows.iter().enumerate() {
            let y = i as f64;
            let colour = COLOURS[i % COLOURS.len()];
            chart
                .draw_series([
                    Rectangle::new(
                        [(r.q1, y - 0.3), (r.q3, y + 0.3)],
                        colour.mix(0.35).filled(),
                    ),
                    Rectangle::new([(r.q1, y - 0.3), (r.q3, y + 0.3)], colour.stroke_width(1)),
                ])
                .map_err(e)?;
            chart
                .draw_series([
                    PathElement::new(
                        vec![(r.median, y - 0.3), (r.median, y + 0.3)],
                        BLACK.stroke_width(2),
                    ),
                    PathElement::new(vec![(r.min, y), (r.q1, y)], colour.stroke_width(1)),
                    PathElement::new(vec![(r.q3, y), (r.max, y)], colour.stroke_width(1)),
                ])
                .map_err(e)?;
        }
        Ok(())
    }
}

/// A viridis-like colour for `t` in [0, 1].
fn viridis(t: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |x: f64, y: f64| (x + (y - x) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

impl Draw for HeatMap {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let (lo, hi) = range(self.values.iter().flatten().flatten().copied());
        let (nw, nh) = (self.widths.len(), self.heights.len());
        let widths = self.widths.clone();
        let heights = self.heights.clone();
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("{} (min {lo:.3}, max {hi:.3}; yellow = high)", self.title),
                ("sans-serif", 20),
            )
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5..(nw as f64 - 0.5), -0.5..(nh as f64 - 0.5))
            .map_err(e)?;
        let label = |v: &[usize], x: f64| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                v.get(i as usize)
                    .map_or_else(String::new, ToString::to_string)
            } else {
                String::new()
            }
        };
        chart
            .configure_mesh()
            .x_desc("width, px")
            .y_desc("height, px")
            .x_labels(nw.clamp(1, 15))
            .y_labels(nh.clamp(1, 12))
            .x_label_formatter(&|x| label(&widths, *x))
            .y_label_formatter(&|y| label(&heights, *y))
            .disable_mesh()
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(e)?;
        for (hi_, row) in self.values.iter().enumerate() {
            for (wi, v) in row.iter().enumerate() {
                let Some(v) = v else { continue };
                let t = (v - lo) / (hi - lo).max(1e-12);
                let (x, y) = (wi as f64, hi_ as f64);
                chart
                    .draw_series([Rectangle::new(
                        [(x - 0.5, y - 0.5), (x + 0.5, y + 0.5)],
                        viridis(t).filled(),
                    )])
                    .map_err(e)?;
            }
        }
        Ok(())
    }
}

/// Writes a figure as `<dir>/<stem>.png` and `.svg`.
pub fn write<D: Draw>(
    dir: &Path,
    stem: &str,
    size: (u32, u32),
    fig: &D,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?;
    crate::plot_out::write(dir, stem, size, fig)
        .map_err(|(path, message)| anyhow::anyhow!("plot {}: {message}", path.display()))
}
