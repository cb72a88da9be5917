//! The report of a `keylo compare` folder: its tables, its plots, every run's trajectory in
//! 3-D per data, and the pictures of runs made with `--images`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::html;
use super::page::Page;
use super::run_parts::{self, Limits, MAP, REFERENCE};
use super::scene::{Cloud, Polyline, Scene};

/// Line colours of the runs (the "tab10" palette of the plots, reference green aside).
const PALETTE: [&str; 9] = [
    "#1f77b4", "#ff7f0e", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf",
    "#7f7f7f",
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
    let plots = plots_html(&dir.join("plots"))?;
    if !plots.is_empty() {
        page.section("Plots", plots);
    }
    for (data, runs) in runs_by_data(&dir.join("runs"))? {
        let scene = trajectories_scene(&data, &runs, limits)?;
        let html = page.scene(scene);
        page.section(&format!("Trajectories on {data} (3-D)"), html);
        for run in &runs {
            if let Some(list) = run_parts::pictured(run)? {
                let html = run_parts::pictures_html(run, &list, 2)?;
                page.section(&format!("Pictures of {}", run_name(run)), html);
                break;
            }
        }
    }
    Ok(page)
}

/// Every SVG figure (PNG where a figure has no SVG) under `plots/`, in name order.
fn plots_html(dir: &Path) -> Result<String> {
    let mut files = Vec::new();
    collect_files(dir, &mut files)?;
    files.sort();
    let mut out = String::new();
    for f in &files {
        let ext = f.extension().and_then(|e| e.to_str()).unwrap_or("");
        let caption = f.strip_prefix(dir).unwrap_or(f).display().to_string();
        if ext == "svg" {
            let svg =
                std::fs::read_to_string(f).with_context(|| format!("reading {}", f.display()))?;
            out.push_str(&html::figure(&svg, &caption));
        } else if ext == "png" && !f.with_extension("svg").is_file() {
            let bytes = std::fs::read(f).with_context(|| format!("reading {}", f.display()))?;
            out.push_str(&html::figure(
                &html::image("image/png", &bytes, &caption),
                &caption,
            ));
        }
    }
    Ok(out)
}

fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries {
        let path = e
            .with_context(|| format!("listing {}", dir.display()))?
            .path();
        if path.is_dir() {
            collect_files(&path, out)?;
        } else {
            out.push(path);
        }
    }
    Ok(())
}

/// Finished runs (folders with a summary.json) under `runs/<data>/<variant>/`, by data.
fn runs_by_data(dir: &Path) -> Result<Vec<(String, Vec<PathBuf>)>> {
    let mut out = Vec::new();
    let mut data_dirs = Vec::new();
    collect_dirs(dir, &mut data_dirs)?;
    for d in data_dirs {
        let mut runs = Vec::new();
        collect_dirs(&d, &mut runs)?;
        runs.retain(|r| r.join("summary.json").is_file());
        if !runs.is_empty() {
            out.push((run_name(&d), runs));
        }
    }
    Ok(out)
}

fn collect_dirs(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries {
        let path = e
            .with_context(|| format!("listing {}", dir.display()))?
            .path();
        if path.is_dir() {
            out.push(path);
        }
    }
    out.sort();
    Ok(())
}

fn run_name(dir: &Path) -> String {
    dir.file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned())
}

/// Every run's trajectory on one data, the first run's reference and local map.
fn trajectories_scene(data: &str, runs: &[PathBuf], limits: Limits) -> Result<Scene> {
    let mut scene = Scene {
        title: format!("trajectories on {data}"),
        clouds: Vec::new(),
        lines: Vec::new(),
    };
    if let Some(first) = runs.first() {
        let reference = first.join(crate::reference_out::FILE);
        if reference.is_file() {
            let name = format!("reference (aligned to {})", run_name(first));
            let path = run_parts::positions(&reference)?;
            scene
                .lines
                .push(Polyline::new(&name, REFERENCE, 7.0, &path));
        }
        let map = first.join("map.ply");
        if map.is_file() {
            let points = crate::cloud_ply::read(&map)?;
            let name = format!("local map of {}", run_name(first));
            scene
                .clouds
                .push(Cloud::thinned(&name, MAP, 1.5, &points, limits.max_points));
        }
    }
    for (i, run) in runs.iter().enumerate() {
        let est = run.join("trajectory.tum");
        if est.is_file() {
            let colour = PALETTE[i % PALETTE.len()];
            let path = run_parts::positions(&est)?;
            scene
                .lines
                .push(Polyline::new(&run_name(run), colour, 3.0, &path));
        }
    }
    Ok(scene)
}
