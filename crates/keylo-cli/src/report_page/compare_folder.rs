//! The report of a `keylo compare` folder: its tables, its plots, every run's trajectory in
//! 3-D per data, and the pictures of runs made with `--images`. A file that cannot be read
//! becomes a note on the page.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::html;
use super::page::Page;
use super::pictures_part;
use super::run_parts::{self, notes_html, soft, Limits, Notes, ESTIMATE, MAP, REFERENCE};
use super::scene::{Cloud, Scene};
use crate::reference_args::file_label;

/// Line colours of the runs after the first (which takes the run report's orange): the
/// "tab10" palette of the plots, its green left to the reference.
const PALETTE: [&str; 8] = [
    "#1f77b4", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf", "#7f7f7f",
];

/// Builds the page of the comparison in `dir`.
pub fn page(dir: &Path, limits: Limits) -> Result<Page> {
    let mut page = Page {
        title: format!("keylo compare — {}", dir.display()),
        ..Page::default()
    };
    let md = dir.join("compare.md");
    let tables =
        std::fs::read_to_string(&md).with_context(|| format!("reading {}", md.display()))?;
    page.section("Tables", super::markdown::to_html(&tables));
    let mut notes = Notes::new();
    let plots = plots_html(&dir.join("plots"), &mut notes);
    if !plots.is_empty() || !notes.is_empty() {
        page.section("Plots", notes_html(&std::mem::take(&mut notes)) + &plots);
    }
    for (data, runs) in runs_by_data(&dir.join("runs")) {
        let scene = trajectories_scene(&data, &runs, limits, &mut notes);
        let html = page.scene(scene) + &notes_html(&std::mem::take(&mut notes));
        page.section(&format!("Trajectories on {data} (3-D)"), html);
        let pictured = runs.iter().find_map(|run| {
            let list = soft(pictures_part::pictured(run), &mut notes).flatten()?;
            Some((run, list))
        });
        if let Some((run, list)) = pictured {
            let html = pictures_part::pictures_html(run, &list, limits.max_pictures, &mut notes);
            let html = notes_html(&std::mem::take(&mut notes)) + &html;
            page.section(&format!("Pictures of {}", file_label(run)), html);
        }
    }
    Ok(page)
}

/// Every SVG figure (PNG where a figure has no SVG) under `plots/`, in name order.
fn plots_html(dir: &Path, notes: &mut Notes) -> String {
    let mut files = Vec::new();
    entries(dir, false, &mut files);
    files.sort();
    let mut out = String::new();
    for f in &files {
        let ext = f.extension().and_then(|e| e.to_str()).unwrap_or("");
        let caption = f.strip_prefix(dir).unwrap_or(f).display().to_string();
        let figure = match ext {
            "svg" => std::fs::read_to_string(f).map(|svg| html::figure(&svg, &caption)),
            "png" if !f.with_extension("svg").is_file() => std::fs::read(f)
                .map(|png| html::figure(&html::image("image/png", &png, &caption), &caption)),
            _ => continue,
        };
        let figure = figure.with_context(|| format!("reading {}", f.display()));
        out.push_str(&soft(figure, notes).unwrap_or_default());
    }
    out
}

/// The files under `dir` (recursively), or with `dirs` its sub-folders only (one level);
/// nothing for a folder that cannot be listed.
fn entries(dir: &Path, dirs: bool, out: &mut Vec<PathBuf>) {
    let Ok(list) = std::fs::read_dir(dir) else {
        return;
    };
    for path in list.flatten().map(|e| e.path()) {
        match (path.is_dir(), dirs) {
            (true, true) => out.push(path),
            (true, false) => entries(&path, false, out),
            (false, false) => out.push(path),
            (false, true) => {}
        }
    }
    out.sort();
}

/// Finished runs (folders with a summary.json) under `runs/<data>/<variant>/`, by data.
fn runs_by_data(dir: &Path) -> Vec<(String, Vec<PathBuf>)> {
    let mut data_dirs = Vec::new();
    entries(dir, true, &mut data_dirs);
    data_dirs
        .into_iter()
        .filter_map(|d| {
            let mut runs = Vec::new();
            entries(&d, true, &mut runs);
            runs.retain(|r| r.join("summary.json").is_file());
            (!runs.is_empty()).then(|| (file_label(&d), runs))
        })
        .collect()
}

/// The reference's name in a run's summary.json (its file name), if it had one.
fn reference_label(run: &Path) -> Option<String> {
    let text = std::fs::read_to_string(run.join("summary.json")).ok()?;
    run_parts::reference_label(&serde_json::from_str(&text).ok()?)
}

/// The first run's local map and reference, then every run's trajectory, on one data.
fn trajectories_scene(data: &str, runs: &[PathBuf], limits: Limits, notes: &mut Notes) -> Scene {
    let mut scene = Scene {
        title: format!("trajectories on {data}"),
        clouds: Vec::new(),
        lines: Vec::new(),
    };
    if let Some(first) = runs.first() {
        let map = first.join("map.ply");
        if map.is_file() {
            if let Some(points) = soft(crate::cloud_ply::read(&map), notes) {
                let name = format!("local map of {}", file_label(first));
                let cloud = Cloud::thinned(&name, MAP, 1.5, &points, limits.max_points);
                scene.clouds.push(cloud);
            }
        }
        let label = reference_label(first).unwrap_or_else(|| "reference".into());
        let name = format!("{label} (aligned to {})", file_label(first));
        let reference = first.join(crate::reference_out::FILE);
        run_parts::push_path(&mut scene, &reference, &name, (REFERENCE, 7.0), notes);
    }
    let colours = std::iter::once(ESTIMATE).chain(PALETTE.iter().copied().cycle());
    for (run, colour) in runs.iter().zip(colours) {
        let est = run.join("trajectory.tum");
        run_parts::push_path(&mut scene, &est, &file_label(run), (colour, 3.0), notes);
    }
    scene
}
