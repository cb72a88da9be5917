//! `keylo keypoints eval --reference DIR`: keylo's per-image results held against the paper
//! authors' (`reference.csv`, `reference.md`).

use std::fmt::Write as _;

use keylo::io::csv_table::table;
use keylo::kpeval::reference::{Agreement, SAME};

/// Metrics held to the goal (time is the machine's, never held).
const HELD: [&str; 7] = [
    "keypoints",
    "robustness_rotation",
    "robustness_scaling",
    "robustness_blur",
    "match_ratio",
    "match_score",
    "distinctiveness",
];

/// Largest difference of medians that counts as agreeing.
pub const MEDIAN_GOAL: f64 = 0.01;

/// Whether a combination meets the goal: the same keypoint count on ≥ 95 % of the images and
/// every held metric's median within [`MEDIAN_GOAL`] (keypoint counts: equal medians).
pub fn meets_goal(a: &Agreement) -> bool {
    a.same_keypoints >= 0.95
        && a.metrics
            .iter()
            .filter(|m| HELD.contains(&m.metric))
            .all(|m| (m.ours_median - m.theirs_median).abs() <= MEDIAN_GOAL)
}

/// `reference.csv`: one line per combination and metric.
pub fn csv(agreements: &[Agreement]) -> String {
    const HEADER: [&str; 9] = [
        "combo",
        "images",
        "same_keypoints",
        "metric",
        "n",
        "ours_median",
        "theirs_median",
        "difference",
        "same_share",
    ];
    let records = agreements.iter().flat_map(|a| {
        a.metrics.iter().map(move |m| {
            vec![
                a.combo.clone(),
                a.images.to_string(),
                a.same_keypoints.to_string(),
                m.metric.to_string(),
                m.n.to_string(),
                m.ours_median.to_string(),
                m.theirs_median.to_string(),
                (m.ours_median - m.theirs_median).to_string(),
                m.same_share.to_string(),
            ]
        })
    });
    table(&HEADER, records)
}

/// `reference.md`: per combination, images, share of equal keypoint counts, and per metric
/// "ours / theirs (share of images with the same value)".
pub fn markdown(agreements: &[Agreement]) -> String {
    let mut out = String::from("| combination | images | same keypoints |");
    let keys: Vec<&str> = HELD
        .iter()
        .copied()
        .chain(std::iter::once("time_ms"))
        .collect();
    for k in &keys {
        let _ = write!(out, " {k} |");
    }
    out.push_str(" goal |\n|---|---:|---:|");
    for _ in &keys {
        out.push_str("---:|");
    }
    out.push_str("---|\n");
    for a in agreements {
        let _ = write!(
            out,
            "| {} | {} | {:.1} % |",
            a.combo,
            a.images,
            100.0 * a.same_keypoints
        );
        for k in &keys {
            let cell = a.metrics.iter().find(|m| m.metric == *k).map_or_else(
                || "–".to_string(),
                |m| {
                    format!(
                        "{} / {} ({:.0} %)",
                        fmt(m.ours_median),
                        fmt(m.theirs_median),
                        100.0 * m.same_share
                    )
                },
            );
            let _ = write!(out, " {cell} |");
        }
        let goal = if a.combo.starts_with("SUPERPOINT") {
            "other weights: no goal"
        } else if meets_goal(a) {
            "met"
        } else {
            "**not met**"
        };
        let _ = writeln!(out, " {goal} |");
    }
    let _ = write!(
        out,
        "\nEach cell: keylo's median / the authors' median over the images both have (share of \
         those images where both values are the same, within {SAME:e}). Goal: the same keypoint \
         count on ≥ 95 % of the images and every median but time within {MEDIAN_GOAL}. Time is \
         each machine's own.\n"
    );
    out
}

fn fmt(v: f64) -> String {
    if v.abs() >= 100.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.3}")
    }
}
