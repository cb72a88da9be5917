//! `keylo report DIR`: one self-contained `report.html` of a run folder or a compare folder:
//! tables, plots, pictures and interactive 3-D views (three.js, inlined), readable offline.

mod compare_folder;
mod html;
mod markdown;
mod page;
mod pictures_part;
mod run_folder;
mod run_parts;
mod run_plots;
mod scene;

use std::process::ExitCode;

use anyhow::{bail, Context, Result};

use std::path::PathBuf;

use clap::Args;
use run_parts::Limits;

pub fn run(args: ReportArgs, quiet: bool) -> Result<ExitCode> {
    let dir = &args.dir;
    let limits = Limits {
        max_points: args.max_points,
        max_pictures: args.max_pictures,
    };
    let page = if dir.join("summary.json").is_file() {
        run_folder::page(dir, limits)?
    } else if dir.join("compare.json").is_file() {
        compare_folder::page(dir, limits)?
    } else if !dir.is_dir() {
        bail!("{}: no such folder", dir.display());
    } else {
        bail!(
            "{}: neither a run folder (no summary.json: `keylo run --out DIR`) nor a compare \
             folder (no compare.json: `keylo compare --out DIR`)",
            dir.display()
        );
    };
    let out = args.out.clone().unwrap_or_else(|| dir.join("report.html"));
    let html = page.render();
    crate::atomic::write(&out, &html).with_context(|| format!("writing {}", out.display()))?;
    if !quiet {
        println!(
            "wrote {} ({:.1} MB, {} 3-D view(s), {} section(s)); open it in a browser",
            out.display(),
            html.len() as f64 / 1e6,
            page.scenes.len(),
            page.sections.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}

#[derive(Debug, Args)]
pub struct ReportArgs {
    /// A run folder (`keylo run --out DIR`) or a compare folder (`keylo compare --out DIR`).
    pub dir: PathBuf,
    /// The page to write (default: DIR/report.html).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Points per 3-D layer at most: larger clouds are thinned (one point in k) and the page
    /// says so.
    #[arg(long, default_value_t = 150_000, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub max_points: usize,
    /// Pictured frames (`keylo run --images`) shown at most, spread over the run.
    #[arg(long, default_value_t = 8, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub max_pictures: usize,
}
