//! `keylo compare`'s figures per data set: trajectories from above, APE over time, points,
//! rate and memory per frame, one line per run.

use std::path::Path;

use anyhow::Result;

use super::error::CompareError;
use super::metrics::Series;
use super::plots;
use super::row::Row;
use super::schedule::Planned;

/// The figures of every data set under `out/plots/<data>/`.
pub(super) fn write_plots(
    out: &Path,
    plans: &[Planned],
    rows: &[Row],
    series: &[Series],
) -> Result<()> {
    let mut data: Vec<&str> = Vec::new();
    for p in plans {
        if !data.contains(&p.data_label.as_str()) {
            data.push(&p.data_label);
        }
    }
    for d in data {
        let dir = out.join("plots").join(d);
        std::fs::create_dir_all(&dir).map_err(|e| CompareError::io(&dir, e))?;
        let runs: Vec<(&Row, &Series)> = rows
            .iter()
            .zip(series)
            .filter(|(r, _)| r.data == d)
            .collect();
        for fig in figures(d, &runs) {
            plots::write(&dir, &fig)?;
        }
    }
    Ok(())
}

fn figures(data: &str, runs: &[(&Row, &Series)]) -> Vec<plots::Figure> {
    let named = |f: &dyn Fn(&Series) -> Vec<(f64, f64)>| -> Vec<plots::Line> {
        runs.iter()
            .map(|(r, s)| plots::Line {
                name: format!("{} [{}]", r.variant, r.verdict),
                points: f(s),
                reference: false,
            })
            .collect()
    };
    let mut top = named(&|s| s.est_xy.clone());
    if let Some((r, s)) = runs.iter().max_by_key(|(_, s)| s.gt_xy.len()) {
        let gt = plots::Line {
            // The reference's file name or --gt-label: it may not be ground truth at all.
            name: r.reference.clone().unwrap_or_else(|| "reference".into()),
            points: s.gt_xy.clone(),
            reference: true,
        };
        top.insert(0, gt);
    }
    let fig = |stem: &str, title: String, x: &str, y: &str, series| plots::Figure {
        file_stem: stem.into(),
        title,
        x_label: x.into(),
        y_label: y.into(),
        series,
    };
    vec![
        fig(
            "trajectories",
            format!("{data}: trajectories from above (SE(3)-aligned)"),
            "x (m)",
            "y (m)",
            top,
        ),
        fig(
            "ape",
            format!("{data}: translation error over time"),
            "time (s)",
            "APE (m)",
            named(&|s| s.ape.clone()),
        ),
        fig(
            "points",
            format!("{data}: points per registered frame"),
            "frame",
            "points to registrar",
            named(&|s| s.points.clone()),
        ),
        fig(
            "rate",
            format!("{data}: odometry rate per frame (un-throttled)"),
            "frame",
            "rate (Hz)",
            named(&|s| s.rate.clone()),
        ),
        fig(
            "rss",
            format!("{data}: resident memory"),
            "frame",
            "RSS (MB)",
            named(&|s| s.rss.clone()),
        ),
    ]
}
