//! Writing one figure as PNG (bitmap backend, encoded with the `png` crate) and SVG.
//!
//! PNG text is drawn with the DejaVu Sans font compiled into the binary
//! (`assets/fonts/`), so no system font is needed at run time.

use std::path::{Path, PathBuf};
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

static FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Distinct colours for series (the "tab10" palette).
pub const COLOURS: [RGBColor; 10] = [
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

fn register_font() {
    REGISTER.call_once(|| {
        // The font is compiled in and known to parse; a failure would only lose PNG text.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Something that draws itself on any plotters backend.
pub trait Draw {
    /// Draws the whole figure on `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static;
}

/// A plot that could not be drawn or encoded: the file and the reason.
pub type PlotError = (PathBuf, String);

/// Writes `<dir>/<stem>.png` and `.svg` of `size` pixels; returns their paths.
pub fn write<D: Draw>(
    dir: &Path,
    stem: &str,
    size: (u32, u32),
    fig: &D,
) -> Result<Vec<PathBuf>, PlotError> {
    register_font();
    let svg = dir.join(format!("{stem}.svg"));
    let png = dir.join(format!("{stem}.png"));
    // Both files are drawn under temporary names and renamed, so a kill leaves no half file.
    let svg_tmp = crate::atomic::temp_path(&svg);
    {
        let root = SVGBackend::new(&svg_tmp, size).into_drawing_area();
        fig.draw(&root).map_err(|e| (svg.clone(), e))?;
        root.present().map_err(|e| (svg.clone(), e.to_string()))?;
    }
    crate::atomic::commit(&svg_tmp, &svg).map_err(|e| (svg.clone(), e.to_string()))?;
    let mut buf = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        fig.draw(&root).map_err(|e| (png.clone(), e))?;
        root.present().map_err(|e| (png.clone(), e.to_string()))?;
    }
    let png_tmp = crate::atomic::temp_path(&png);
    encode_png(&png_tmp, &buf, size).map_err(|e| (png.clone(), e))?;
    crate::atomic::commit(&png_tmp, &png).map_err(|e| (png.clone(), e.to_string()))?;
    Ok(vec![png, svg])
}

/// The figure as SVG text, for pages that inline it.
pub fn svg_string<D: Draw>(size: (u32, u32), fig: &D) -> Result<String, String> {
    register_font();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        fig.draw(&root)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

fn encode_png(path: &Path, rgb: &[u8], size: (u32, u32)) -> Result<(), String> {
    let bytes = rgb_png(rgb, size).map_err(|e| e.to_string())?;
    std::fs::write(path, bytes).map_err(|e| e.to_string())
}

/// 8-bit RGB pixels (row-major, `size` = width × height) as PNG bytes.
pub fn rgb_png(rgb: &[u8], size: (u32, u32)) -> Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut bytes, size.0, size.1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header()?;
    w.write_image_data(rgb)?;
    w.finish()?;
    Ok(bytes)
}
