//! Plots of a comparison (plotters; PNG through the bitmap backend and the `png` crate, and
//! SVG): trajectories from above against ground truth, APE over time, points per frame,
//! odometry rate per frame and resident memory per frame, one set per data.
//!
//! PNG text is drawn with the DejaVu Sans font compiled into the binary
//! (`assets/fonts/`), so no system font is needed at run time.

use std::path::{Path, PathBuf};
use std::sync::Once;

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
/// Distinct colours for the runs (the "tab10" palette); black is the ground truth.
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The font is compiled in and known to parse; a failure would only lose PNG text.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Writes `<dir>/<stem>.png` and `.svg`; returns their paths. A figure without points is
/// skipped (empty list).
pub fn write(dir: &Path, fig: &Figure) -> Result<Vec<PathBuf>, CompareError> {
    if fig.series.iter().all(|s| s.points.is_empty()) {
        return Ok(Vec::new());
    }
    register_font();
    let svg = dir.join(format!("{}.svg", fig.file_stem));
    let png = dir.join(format!("{}.png", fig.file_stem));
    let plot_err = |path: &Path, e: String| CompareError::Plot {
        path: path.to_path_buf(),
        message: e,
    };
    {
        let root = SVGBackend::new(&svg, SIZE).into_drawing_area();
        draw(&root, fig).map_err(|e| plot_err(&svg, e))?;
        root.present().map_err(|e| plot_err(&svg, e.to_string()))?;
    }
    let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
        draw(&root, fig).map_err(|e| plot_err(&png, e))?;
        root.present().map_err(|e| plot_err(&png, e.to_string()))?;
    }
    encode_png(&png, &buf).map_err(|e| plot_err(&png, e))?;
    Ok(vec![png, svg])
}

fn encode_png(path: &Path, rgb: &[u8]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| e.to_string())?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), SIZE.0, SIZE.1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(|e| e.to_string())?;
    w.write_image_data(rgb).map_err(|e| e.to_string())
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
            COLOURS[(colour - 1) % COLOURS.len()].stroke_width(2)
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
