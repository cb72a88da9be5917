//! The realism tables: Markdown (keypoint counts against the real interquartile range, the
//! match metrics against the real medians, the other metrics, histogram distances, the goal),
//! CSV of every quartile, CSV of the histograms, JSON.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use keylo::kpeval::realism::{distance, Distance, GRADIENT_BIN_WIDTH, ROW_BANDS};
use keylo::kpeval::Quartiles;

use super::ImageSet;

/// Largest difference from the real median that counts as alike, for match ratio and score.
const MATCH_TOLERANCE: f64 = 0.1;

/// Metrics beside the keypoint count and the match metrics, by median.
const OTHER_METRICS: &[&str] = &[
    "robustness_rotation",
    "robustness_scaling_corrected",
    "robustness_blur",
    "distinctiveness",
];

/// Writes realism.md, realism.csv, histograms.csv and realism.json into `out`; returns the
/// Markdown.
pub fn write(out: &Path, sets: &[ImageSet], heading: &str) -> Result<String> {
    let md = markdown(sets, heading);
    let file = |name: &str, text: &str| {
        let p = out.join(name);
        std::fs::write(&p, text).with_context(|| format!("writing {}", p.display()))
    };
    file("realism.md", &md)?;
    file("realism.csv", &quartiles_csv(sets))?;
    file("histograms.csv", &histograms_csv(sets))?;
    file("realism.json", &serde_json::to_string_pretty(&json(sets))?)?;
    Ok(md)
}

pub(super) fn quartiles<'a>(set: &'a ImageSet, combo: &str, metric: &str) -> Option<&'a Quartiles> {
    set.summaries
        .iter()
        .find(|s| s.combo == combo)
        .and_then(|s| s.get(metric))
}

/// Whether `q`'s median lies in the real interquartile range.
pub(super) fn inside(real: &Quartiles, q: &Quartiles) -> bool {
    q.median >= real.q1 && q.median <= real.q3
}

pub(super) fn close(real: &Quartiles, q: &Quartiles) -> bool {
    (q.median - real.median).abs() <= MATCH_TOLERANCE
}

fn distances(real: &ImageSet, set: &ImageSet) -> (Distance, Distance) {
    (
        distance(&real.histograms.intensity, &set.histograms.intensity, 1.0),
        distance(
            &real.histograms.gradient,
            &set.histograms.gradient,
            GRADIENT_BIN_WIDTH,
        ),
    )
}

pub fn markdown(sets: &[ImageSet], heading: &str) -> String {
    let Some((real, sim)) = sets.split_first() else {
        return String::new();
    };
    let mut md = format!(
        "# Simulated against real images\n\n{heading}\n\n{} real images; {} simulated frames \
         per channel from {} layouts; all resized to 1024×64 (linear) as the keypoint study \
         does.\n\n",
        real.histograms.images,
        sim.first().map_or(0, |s| s.histograms.images),
        sim.first().map_or(0, |s| s.sequences)
    );
    goal(&mut md, real, sim);
    keypoint_table(&mut md, real, sim);
    median_table(
        &mut md,
        "## Match ratio and match score\n\nMedian; ✓: within 0.1 of the real median.\n\n",
        &["match_ratio", "match_score"],
        Some(close),
        (real, sim),
    );
    median_table(
        &mut md,
        "## The other metrics\n\nMedians.\n\n",
        OTHER_METRICS,
        None,
        (real, sim),
    );
    histogram_table(&mut md, real, sim);
    row_table(&mut md, real, sim);
    md
}

/// The goal, for the simulated signal as the real images were made.
fn goal(md: &mut String, real: &ImageSet, sim: &[ImageSet]) {
    let Some(signal) = sim.iter().find(|s| s.name == "sim signal") else {
        return;
    };
    let check = |metric: &str, test: fn(&Quartiles, &Quartiles) -> bool| {
        let mut met = Vec::new();
        let mut missed = Vec::new();
        for c in &real.summaries {
            let pair = (
                quartiles(real, &c.combo, metric),
                quartiles(signal, &c.combo, metric),
            );
            match pair {
                (Some(r), Some(q)) if test(r, q) => met.push(c.combo.as_str()),
                _ => missed.push(c.combo.as_str()),
            }
        }
        (met, missed)
    };
    let _ = writeln!(md, "## Goal: the simulated signal images\n");
    let lines = [
        (
            "keypoint count inside the real interquartile range",
            check("keypoints", inside),
        ),
        (
            "match ratio within 0.1 of the real median",
            check("match_ratio", close),
        ),
        (
            "match score within 0.1 of the real median",
            check("match_score", close),
        ),
    ];
    for (what, (met, missed)) in lines {
        let n = met.len() + missed.len();
        let _ = write!(md, "- {what}: **{} of {n}**", met.len());
        if !missed.is_empty() {
            let _ = write!(md, " (not: {})", missed.join(", "));
        }
        md.push('\n');
    }
    md.push('\n');
}

fn header(md: &mut String, first: &[&str], sim: &[ImageSet]) {
    let names: Vec<&str> = sim.iter().map(|s| s.name.as_str()).collect();
    let cols = [first, &names].concat();
    let _ = writeln!(md, "| {} |", cols.join(" | "));
    let _ = writeln!(md, "|{}", "---|".repeat(cols.len()));
}

/// Whether a simulated figure counts as alike (marked ✓), given the real quartiles.
type Alike = fn(&Quartiles, &Quartiles) -> bool;

/// One cell per simulated set: its median of `metric` for `combo`, ✓ when `alike`.
fn sim_cells(
    md: &mut String,
    sim: &[ImageSet],
    combo: &str,
    metric: &str,
    real: &Quartiles,
    decimals: usize,
    alike: Option<Alike>,
) {
    for s in sim {
        match quartiles(s, combo, metric) {
            Some(q) => {
                let mark = if alike.is_some_and(|f| f(real, q)) {
                    " ✓"
                } else {
                    ""
                };
                let _ = write!(md, " {:.*}{mark} |", decimals, q.median);
            }
            None => md.push_str(" – |"),
        }
    }
    md.push('\n');
}

fn keypoint_table(md: &mut String, real: &ImageSet, sim: &[ImageSet]) {
    md.push_str(
        "## Keypoints per image\n\nMedian; ✓: inside the real images' interquartile range.\n\n",
    );
    header(md, &["combination", "real median [q1, q3]"], sim);
    for c in &real.summaries {
        let Some(r) = c.get("keypoints") else {
            continue;
        };
        let _ = write!(
            md,
            "| {} | {:.0} [{:.0}, {:.0}] |",
            c.combo, r.median, r.q1, r.q3
        );
        sim_cells(md, sim, &c.combo, "keypoints", r, 0, Some(inside));
    }
    md.push('\n');
}

/// A table of medians of `metrics`, one row per combination and metric.
fn median_table(
    md: &mut String,
    title: &str,
    metrics: &[&str],
    alike: Option<Alike>,
    sets: (&ImageSet, &[ImageSet]),
) {
    let (real, sim) = sets;
    md.push_str(title);
    header(md, &["combination", "metric", "real"], sim);
    for c in &real.summaries {
        for &metric in metrics {
            let Some(r) = c.get(metric) else {
                continue;
            };
            let _ = write!(md, "| {} | {metric} | {:.3} |", c.combo, r.median);
            sim_cells(md, sim, &c.combo, metric, r, 3, alike);
        }
    }
    md.push('\n');
}

fn histogram_table(md: &mut String, real: &ImageSet, sim: &[ImageSet]) {
    md.push_str(
        "## Histograms\n\nMean over each set's resized images. EMD: earth mover's distance to \
         the real images' histogram (grey levels; gradient: grey levels per pixel of Sobel \
         magnitude); Hellinger: 0 same, 1 disjoint. Shift: median horizontal shift between \
         consecutive images (pixels at 1024×64, phase correlation); change: median mean \
         absolute difference between consecutive images once the shift is undone (grey \
         levels; a still sensor's is its noise) — the match metrics fall as either grows, so \
         compare sets that move alike.\n\n",
    );
    md.push_str(
        "| images | shift | change | mean grey | intensity EMD | intensity Hellinger | mean \
         gradient | gradient EMD | gradient Hellinger |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let _ = writeln!(
        md,
        "| real | {} | {} | {:.1} | – | – | {:.1} | – | – |",
        shift(real),
        change(real),
        real.histograms.mean_intensity(),
        real.histograms.mean_gradient()
    );
    for s in sim {
        let (i, g) = distances(real, s);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.1} | {:.1} | {:.3} | {:.1} | {:.1} | {:.3} |",
            s.name,
            shift(s),
            change(s),
            s.histograms.mean_intensity(),
            i.emd,
            i.hellinger,
            s.histograms.mean_gradient(),
            g.emd,
            g.hellinger
        );
    }
}

fn shift(set: &ImageSet) -> String {
    set.moved
        .map_or_else(|| "–".into(), |m| format!("{:.2}", m.shift))
}

fn change(set: &ImageSet) -> String {
    set.moved
        .map_or_else(|| "–".into(), |m| format!("{:.2}", m.change))
}

/// Mean grey per row band, real and simulated, and each set's mean absolute difference from
/// the real profile.
fn row_table(md: &mut String, real: &ImageSet, sim: &[ImageSet]) {
    md.push_str(
        "\n## Row profile\n\nMean grey level per eighth of the image's rows, top (ceiling, \
         sky) first; difference: the mean absolute difference from the real profile. Row and \
         column residual: the median |pixel − mean of the pixels above and below| (left and \
         right), grey levels — how much rows differ from their neighbours.\n\n",
    );
    let bands: Vec<String> = (1..=ROW_BANDS)
        .map(|b| format!("rows {b}/{ROW_BANDS}"))
        .collect();
    let _ = writeln!(
        md,
        "| images | {} | difference | row residual | column residual |",
        bands.join(" | ")
    );
    let _ = writeln!(md, "|{}", "---|".repeat(ROW_BANDS + 4));
    let r = &real.histograms.row_profile;
    for s in std::iter::once(real).chain(sim) {
        let p = &s.histograms.row_profile;
        let cells: Vec<String> = p.iter().map(|v| format!("{v:.1}")).collect();
        let diff = p.iter().zip(r).map(|(a, b)| (a - b).abs()).sum::<f64>() / ROW_BANDS as f64;
        let h = &s.histograms;
        let _ = writeln!(
            md,
            "| {} | {} | {diff:.1} | {:.1} | {:.1} |",
            s.name,
            cells.join(" | "),
            h.median_row_residual(),
            h.median_column_residual()
        );
    }
}

fn quartiles_csv(sets: &[ImageSet]) -> String {
    let mut csv = String::from("set,combination,metric,n,q1,median,q3,mean\n");
    for s in sets {
        for c in &s.summaries {
            for (metric, q) in &c.metrics {
                let _ = writeln!(
                    csv,
                    "{},{},{metric},{},{},{},{},{}",
                    s.name, c.combo, q.n, q.q1, q.median, q.q3, q.mean
                );
            }
        }
    }
    csv
}

fn histograms_csv(sets: &[ImageSet]) -> String {
    let names: Vec<&str> = sets.iter().map(|s| s.name.as_str()).collect();
    let mut csv = format!("histogram,bin_start,{}\n", names.join(","));
    let mut rows = |kind: &str, width: f64, get: fn(&ImageSet) -> &Vec<f64>| {
        let bins = sets.first().map_or(0, |s| get(s).len());
        for b in 0..bins {
            let values: Vec<String> = sets.iter().map(|s| get(s)[b].to_string()).collect();
            let _ = writeln!(csv, "{kind},{},{}", b as f64 * width, values.join(","));
        }
    };
    rows("intensity", 1.0, |s| &s.histograms.intensity);
    rows("gradient", GRADIENT_BIN_WIDTH, |s| &s.histograms.gradient);
    csv
}

fn json(sets: &[ImageSet]) -> serde_json::Value {
    let real = sets.first();
    let entries: Vec<serde_json::Value> = sets
        .iter()
        .map(|s| {
            let d = real.map(|r| distances(r, s));
            serde_json::json!({
                "name": s.name,
                "images": s.histograms.images,
                "mean_intensity": s.histograms.mean_intensity(),
                "mean_gradient": s.histograms.mean_gradient(),
                "row_profile": s.histograms.row_profile,
                "median_row_residual": s.histograms.median_row_residual(),
                "median_column_residual": s.histograms.median_column_residual(),
                "median_shift_px": s.moved.map(|m| m.shift),
                "median_change": s.moved.map(|m| m.change),
                "intensity_distance": d.map(|d| d.0),
                "gradient_distance": d.map(|d| d.1),
                "combos": s.summaries,
            })
        })
        .collect();
    serde_json::json!({ "sets": entries })
}
