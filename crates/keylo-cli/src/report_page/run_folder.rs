//! The report of one run folder.

use std::path::Path;

use anyhow::Result;

use super::html::{self, escape};
use super::page::Page;
use super::run_parts::{self, Limits};

/// Builds the page of the run in `dir`.
pub fn page(dir: &Path, limits: Limits) -> Result<Page> {
    let (summary, headline, all) = run_parts::summary_tables(dir)?;
    let text = |key: &str| {
        summary
            .get(key)
            .and_then(|v| v.as_str())
            .unwrap_or("")
            .to_string()
    };
    let mut page = Page {
        title: format!("keylo run — {}", dir.display()),
        subtitle: vec![
            format!("source: {}", text("source")),
            format!("config: {}", text("config")),
            format!("keylo {}", text("keylo_version")),
        ],
        ..Page::default()
    };
    if let Some(f) = summary.get("failed").filter(|f| !f.is_null()) {
        page.section(
            "Failure",
            format!(
                "<p class=\"warn\">The run stopped early: {}</p>",
                escape(&f.to_string())
            ),
        );
    }
    let warning = summary
        .get("association_warning")
        .and_then(|w| w.as_str())
        .map(|w| format!("<p class=\"warn\">Reference timing: {}</p>", escape(w)))
        .unwrap_or_default();
    page.section("Summary", format!("{warning}{headline}"));
    let reference = summary
        .get("ground_truth")
        .and_then(|v| v.as_str())
        .unwrap_or("reference");
    let mut view = String::new();
    match run_parts::map_scene(dir, reference, limits)? {
        Some(scene) => view.push_str(&page.scene(scene)),
        None => view.push_str("<p class=\"note\">This run has no map.ply and no trajectory.</p>"),
    }
    if !dir.join(crate::reference_out::FILE).is_file() {
        view.push_str(
            "<p class=\"note\">No reference trajectory: run with --gt (or data with its own \
             ground truth) to see it here.</p>",
        );
    }
    page.section("Local map and trajectory (3-D)", view);
    let pictured = run_parts::pictured(dir)?;
    match &pictured {
        Some(list) => {
            if let Some(scene) = run_parts::frame_scene(dir, list, limits)? {
                let html = page.scene(scene);
                page.section("One frame: raw and registered points (3-D)", html);
            }
            let html = run_parts::pictures_html(dir, list, limits.max_pictures)?;
            page.section("Pictures", html);
        }
        None => page.section(
            "Pictures",
            "<p class=\"note\">No pictures: run with <code>--images N</code> to picture every \
             N-th frame (keypoints, registered pixels, top view) and one frame's points in 3-D.</p>"
                .into(),
        ),
    }
    let plots = super::run_plots::frame_plots(dir)?;
    if !plots.is_empty() {
        let html: String = plots.iter().map(|(t, svg)| html::figure(svg, t)).collect();
        page.section("Per frame", html);
    }
    page.section(
        "Every figure of summary.json",
        format!("<details><summary>show</summary>{all}</details>"),
    );
    if let Ok(config) = std::fs::read_to_string(dir.join("config.toml")) {
        page.section(
            "Config (resolved)",
            format!("<pre>{}</pre>", escape(&config)),
        );
    }
    Ok(page)
}
