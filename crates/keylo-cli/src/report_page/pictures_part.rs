//! The pictures of a run made with `--images` in a report: the pictured frames' PNGs and one
//! frame's raw and registered points in 3-D. Files are taken from `images/pictures.json` only
//! by bare name, inside `images/`; one that cannot be read is noted.

use std::path::Path;

use anyhow::{bail, Context, Result};

use super::html::{self, escape};
use super::run_parts::{soft, Limits, Notes, MAP, SELECTED};
use super::scene::{Cloud, Scene};
use crate::overlay::Pictured;

/// The `images/pictures.json` list of `keylo run --images`, if the run has one.
pub fn pictured(dir: &Path) -> Result<Option<Vec<Pictured>>> {
    let path = dir.join("images").join(crate::overlay::INDEX);
    if !path.is_file() {
        return Ok(None);
    }
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let list = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a list of pictured frames", path.display()))?;
    Ok(Some(list))
}

/// `dir/images/NAME` for a bare file name `NAME` (no folder, not hidden).
fn image_file(dir: &Path, name: &str) -> Result<std::path::PathBuf> {
    let bare = !name.is_empty()
        && !name.starts_with('.')
        && !name.contains(['/', '\\'])
        && Path::new(name).file_name() == Some(std::ffi::OsStr::new(name));
    if !bare {
        bail!(
            "{}: `{name}` is not a file name in images/",
            dir.join("images").join(crate::overlay::INDEX).display()
        );
    }
    Ok(dir.join("images").join(name))
}

/// One frame's raw points and the registered ones (sensor frame).
pub fn frame_scene(
    dir: &Path,
    pictured: &[Pictured],
    limits: Limits,
    notes: &mut Notes,
) -> Option<Scene> {
    let (frame, [raw, selected]) = pictured
        .iter()
        .find_map(|p| p.clouds.clone().map(|c| (p.frame, c)))?;
    let read = |name: &str| crate::cloud_ply::read(&image_file(dir, name)?);
    let raw = soft(read(&raw), notes)?;
    let selected = soft(read(&selected), notes)?;
    let registered = "points given to the registrar";
    Some(Scene {
        title: format!("frame {frame}: raw and registered points"),
        clouds: vec![
            Cloud::thinned("raw points", MAP, 1.5, &raw, limits.max_points),
            Cloud::thinned(registered, SELECTED, 3.5, &selected, limits.max_points),
        ],
        lines: Vec::new(),
    })
}

/// The pictures of at most `max` frames, spread evenly over those pictured.
pub fn pictures_html(dir: &Path, pictured: &[Pictured], max: usize, notes: &mut Notes) -> String {
    let step = pictured.len().div_ceil(max.max(1)).max(1);
    let mut out = String::new();
    if step > 1 {
        out.push_str(&format!(
            "<p class=\"note\">{} frames were pictured; one in {step} is shown here (all are \
             in {}).</p>",
            pictured.len(),
            escape(&dir.join("images").display().to_string())
        ));
    }
    for p in pictured.iter().step_by(step) {
        out.push_str(&format!(
            "<h3>Frame {}</h3><div class=\"pictures\">",
            p.frame
        ));
        for i in &p.images {
            let caption = format!(
                "{}: {} keypoints (yellow circles: size and orientation, red: position); \
                 tinted blue: pixels whose points were registered",
                i.image, i.keypoints
            );
            out.push_str(&soft(png_figure(dir, &i.file, &caption), notes).unwrap_or_default());
        }
        out.push_str("</div><div class=\"pictures top\">");
        let t = &p.top;
        let caption = format!(
            "from above, forward up: {} raw points (grey), {} registered (orange); rings \
             every {} m, edge at {} m",
            t.raw_points, t.selected_points, t.ring_step_m, t.half_extent_m
        );
        out.push_str(&soft(png_figure(dir, &t.file, &caption), notes).unwrap_or_default());
        out.push_str("</div>");
    }
    out
}

fn png_figure(dir: &Path, name: &str, caption: &str) -> Result<String> {
    let path = image_file(dir, name)?;
    let bytes = std::fs::read(&path).with_context(|| format!("reading {}", path.display()))?;
    Ok(html::figure(
        &html::image("image/png", &bytes, name),
        caption,
    ))
}
