//! The report of one run folder.

use std::path::Path;

use anyhow::Result;

use super::html::{self, escape};
use super::page::Page;
use super::pictures_part;
use super::run_parts::{self, notes_html, soft, Limits, Notes};

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
    let reference = run_parts::reference_label(&summary).unwrap_or_else(|| "reference".into());
    let mut notes = Notes::new();
    let mut view = String::new();
    match run_parts::map_scene(dir, &reference, limits, &mut notes) {
        Some(scene) => view.push_str(&page.scene(scene)),
        None => view.push_str("<p class=\"note\">This run has no map.ply and no trajectory.</p>"),
    }
    view.push_str(&notes_html(&std::mem::take(&mut notes)));
    if !dir.join(crate::reference_out::FILE).is_file() {
        view.push_str(
            "<p class=\"note\">No reference trajectory: run with --gt (or data with its own \
             ground truth) to see it here.</p>",
        );
    }
    page.section("Local map and trajectory (3-D)", view);
    let pictured = soft(pictures_part::pictured(dir), &mut notes).flatten();
    match &pictured {
        Some(list) => {
            if let Some(scene) = pictures_part::frame_scene(dir, list, limits, &mut notes) {
                let html = page.scene(scene) + &notes_html(&std::mem::take(&mut notes));
                page.section("One frame: raw and registered points (3-D)", html);
            }
            let html = pictures_part::pictures_html(dir, list, limits.max_pictures, &mut notes);
            page.section("Pictures", notes_html(&std::mem::take(&mut notes)) + &html);
        }
        None => page.section(
            "Pictures",
            "<p class=\"note\">No pictures: run with <code>--images N</code> to picture every \
             N-th frame (keypoints, registered pixels, top view) and one frame's points in 3-D.</p>"
                .into(),
        ),
    }
    let plots = soft(super::run_plots::frame_plots(dir), &mut notes).unwrap_or_default();
    if !plots.is_empty() || !notes.is_empty() {
        let html: String = notes_html(&std::mem::take(&mut notes))
            + &plots
                .iter()
                .map(|(t, svg)| html::figure(svg, t))
                .collect::<String>();
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
