//! The still and the moving comparison side by side (realism.md of `--moving-start`): the
//! goal for each half, and per detector the real quartiles beside the simulated medians.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use keylo::kpeval::Quartiles;

use super::motion::Motion;
use super::report::{close, inside, quartiles};
use super::ImageSet;

/// The two halves and how they were made.
pub struct Halves<'a> {
    pub still: &'a [ImageSet],
    pub moving: &'a [ImageSet],
    /// First real image of each half.
    pub still_first: usize,
    pub moving_first: usize,
    pub motion: &'a Motion,
}

/// The goal's three tests: (metric, words, test).
type Test = (
    &'static str,
    &'static str,
    fn(&Quartiles, &Quartiles) -> bool,
);
const TESTS: [Test; 3] = [
    (
        "keypoints",
        "keypoint count inside the real interquartile range",
        inside,
    ),
    (
        "match_ratio",
        "match ratio within 0.1 of the real median",
        close,
    ),
    (
        "match_score",
        "match score within 0.1 of the real median",
        close,
    ),
];

/// The real set and the simulated signal (as the driver makes it) of one half.
fn pair(sets: &[ImageSet]) -> Option<(&ImageSet, &ImageSet)> {
    let real = sets.first()?;
    let sim = sets.iter().find(|s| s.name == "sim signal")?;
    Some((real, sim))
}

/// `met of n` for one test of one half.
fn score(sets: &[ImageSet], metric: &str, test: fn(&Quartiles, &Quartiles) -> bool) -> String {
    let Some((real, sim)) = pair(sets) else {
        return "-".into();
    };
    let n = real.summaries.len();
    let met = (real.summaries.iter())
        .filter(|c| {
            match (
                quartiles(real, &c.combo, metric),
                quartiles(sim, &c.combo, metric),
            ) {
                (Some(r), Some(q)) => test(r, q),
                _ => false,
            }
        })
        .count();
    format!("{met} of {n}")
}

/// The real quartiles and the simulated median with its verdict, for one half.
fn cells(
    sets: &[ImageSet],
    combo: &str,
    metric: &str,
    test: fn(&Quartiles, &Quartiles) -> bool,
) -> (String, String) {
    let Some((real, sim)) = pair(sets) else {
        return ("-".into(), "-".into());
    };
    let digits = if metric == "keypoints" { 0 } else { 3 };
    match (
        quartiles(real, combo, metric),
        quartiles(sim, combo, metric),
    ) {
        (Some(r), Some(q)) => (
            format!(
                "{:.digits$} [{:.digits$}, {:.digits$}]",
                r.median, r.q1, r.q3
            ),
            format!(
                "{:.digits$} {}",
                q.median,
                if test(r, q) { "✓" } else { "✗" }
            ),
        ),
        _ => ("-".into(), "-".into()),
    }
}

/// The Markdown of both halves.
pub fn markdown(h: &Halves, heading: &str) -> String {
    let images = |sets: &[ImageSet]| sets.first().map_or(0, |s| s.histograms.images);
    let layouts = h.still.get(1).map_or(0, |s| s.sequences);
    let m = h.motion;
    let mut md = format!(
        "# Simulated against real images: still and moving\n\n{heading}\n\n\
         - **Still**: real images {a}–{b}; the simulated sensor held still.\n\
         - **Moving**: real images {c}–{d}: between consecutive images (at 1024×64) a median \
         shift of {rs:.2} px and a change beyond it of {rc:.2} grey levels. Simulated: the \
         lab's walk from full speed, started {lap} of a lap on, `speed_scale = {speed:.4}`, \
         `sway_scale = {sway:.4}`, chosen so that the two move alike (shift {ss:.2} px, change \
         {sc:.2} on the first {n} layouts; held still, the simulated change is {still:.2}, its \
         noise alone).\n\
         - {layouts} simulated layouts in each half; the simulated signal as Ouster's driver \
         makes its images; each half in full in `still/` and `moving/`.\n\n",
        a = h.still_first,
        b = h.still_first + images(h.still).saturating_sub(1),
        c = h.moving_first,
        d = h.moving_first + images(h.moving).saturating_sub(1),
        rs = m.real.shift,
        rc = m.real.change,
        lap = m.config.start_lap,
        speed = m.config.speed_scale,
        sway = m.config.sway_scale,
        ss = m.sim.shift,
        sc = m.sim.change,
        n = m.layouts,
        still = m.still.change,
    );
    md.push_str("## Goal\n\n| | still | moving |\n|---|---|---|\n");
    for (metric, words, test) in TESTS {
        let _ = writeln!(
            md,
            "| {words} | {} | {} |",
            score(h.still, metric, test),
            score(h.moving, metric, test)
        );
    }
    md.push_str(
        "\n## Per detector\n\nReal: median [q1, q3]; simulated: median, ✓ where the goal's \
         test passes.\n\n| combination | metric | still, real | still, simulated | moving, \
         real | moving, simulated |\n|---|---|---|---|---|---|\n",
    );
    let combos: Vec<String> = h
        .still
        .first()
        .map(|r| r.summaries.iter().map(|c| c.combo.clone()).collect())
        .unwrap_or_default();
    for combo in &combos {
        for (metric, _, test) in TESTS {
            let (sr, ss) = cells(h.still, combo, metric, test);
            let (mr, ms) = cells(h.moving, combo, metric, test);
            let _ = writeln!(md, "| {combo} | {metric} | {sr} | {ss} | {mr} | {ms} |");
        }
    }
    md
}

/// Writes realism.md (both halves) into `out`; returns it.
pub fn write(out: &Path, h: Halves, heading: &str) -> Result<String> {
    let md = markdown(&h, heading);
    let p = out.join("realism.md");
    std::fs::write(&p, &md).with_context(|| format!("writing {}", p.display()))?;
    Ok(md)
}
