//! The comparison as tables: every run's figures (Markdown, CSV, JSON), and the paper's
//! shapes: the neighbour-size accuracy and points tables (variants × data) and the
//! KISS-ICP / NDT performance table (indicators × variants, one per data).

use std::fmt::Write as _;

use serde_json::Value;

use super::association;
use super::row::{describe, Criterion, Row};

/// Columns of the full table: (JSON/CSV field, Markdown header, decimals).
const COLUMNS: [(&str, &str, usize); 27] = [
    ("data", "data", 0),
    ("variant", "variant", 0),
    ("config", "config", 0),
    ("registrar", "registrar", 0),
    ("downsampler", "downsampler", 0),
    ("verdict", "verdict", 0),
    ("reason", "reason", 0),
    ("resumed", "resumed", 0),
    ("frames", "frames", 0),
    ("degenerate_frames", "degenerate frames", 0),
    ("associated_poses", "poses vs GT", 0),
    ("trans_mean_m", "trans. mean (m)", 3),
    ("trans_rmse_m", "trans. RMSE (m)", 3),
    ("trans_max_m", "trans. max (m)", 3),
    ("rot_mean_deg", "rot. mean (deg)", 2),
    ("rot_rmse_deg", "rot. RMSE (deg)", 2),
    ("rpe_trans_m", "RPE trans (m/frame)", 4),
    ("rpe_rot_deg", "RPE rot (deg/frame)", 3),
    ("cpu_percent", "CPU (%)", 0),
    ("peak_rss_mb", "peak RSS (MB)", 1),
    ("frames_late", "late frames", 0),
    ("mean_points", "points/frame", 0),
    ("mean_registered_points", "registered/frame", 0),
    ("odometry_hz", "rate (Hz)", 1),
    ("rate_vs_raw", "rate / raw", 2),
    ("associated", "associated", 0),
    ("reference", "reference", 0),
];

fn columns() -> impl Iterator<Item = &'static (&'static str, &'static str, usize)> {
    COLUMNS.iter()
}

fn cell(row: &Value, key: &str, digits: usize) -> String {
    match row.get(key) {
        None | Some(Value::Null) => String::new(),
        Some(Value::String(s)) => s.clone(),
        Some(Value::Bool(b)) => b.to_string(),
        Some(Value::Number(n)) if n.is_f64() => n
            .as_f64()
            .map_or(String::new(), |v| format!("{v:.digits$}")),
        Some(v) => v.to_string(),
    }
}

fn as_values(rows: &[Row]) -> Vec<Value> {
    rows.iter()
        .map(|r| serde_json::to_value(r).unwrap_or(Value::Null))
        .collect()
}

/// CSV of every run, full precision for numbers (quoted where a field needs it).
pub fn csv(rows: &[Row]) -> String {
    let header: Vec<&str> = columns().map(|c| c.0).collect();
    let records = as_values(rows).into_iter().map(|v| {
        columns()
            .map(|c| match v.get(c.0) {
                Some(Value::Number(n)) => n.to_string(),
                _ => cell(&v, c.0, 0),
            })
            .collect::<Vec<String>>()
    });
    keylo::io::csv_table::table(&header, records)
}

/// JSON of every run, with the divergence criterion.
pub fn json(rows: &[Row], crit: &Criterion) -> String {
    let doc = serde_json::json!({
        "criterion": { "max_ape_m": crit.max_ape_m, "max_step_m": crit.max_step_m,
                       "t_max_diff_s": crit.t_max_diff_s,
                       "text": describe(crit) },
        "runs": rows,
        "warnings": association::warnings(rows)
            .into_iter()
            .map(|(data, text)| serde_json::json!({ "data": data, "text": text }))
            .collect::<Vec<_>>(),
    });
    serde_json::to_string_pretty(&doc).unwrap_or_default()
}

/// The Markdown report: the paper-shaped tables, then every run's figures.
pub fn markdown(rows: &[Row], crit: &Criterion) -> String {
    let mut md = String::from("# keylo compare\n\n");
    let data = unique(rows.iter().map(|r| r.data.clone()));
    let variants = unique(rows.iter().map(|r| r.variant.clone()));
    md.push_str("## Accuracy: translation error (mean/RMSE, m), rotation error (mean, deg)\n\n");
    md.push_str(&grid_table(rows, &variants, &data, accuracy_cell));
    md.push_str(&association::markdown(rows));
    md.push_str("\n## Points per registered frame (mean, handed to the registrar)\n\n");
    md.push_str(&grid_table(rows, &variants, &data, |r| {
        r.mean_points.map_or("-".into(), |p| format!("{p:.0}"))
    }));
    if let Some(speed) = rows.iter().find_map(|r| r.playback_speed) {
        let _ = write!(
            md,
            "\nPlayed back at {speed}× the sensor's rate (`--realtime`): CPU (%) and peak RSS \
             are those at that rate; a run whose odometry fell behind counts late frames.\n"
        );
    }
    for d in &data {
        let _ = write!(md, "\n## Performance on {d}\n\n");
        md.push_str(&performance(rows, d, &variants));
    }
    md.push_str("\n## Every run\n\n");
    md.push_str(&full_table(rows));
    md.push_str(&association::markdown(rows));
    md.push_str(&degenerate_note(rows));
    let _ = write!(md, "\nDivergence criterion: {}.\n", describe(crit));
    md.push_str(
        "Errors are after SE(3) Umeyama alignment of the positions (as `evo_ape -a`); on a \
         nearly straight path the alignment's rotation about the path axis is taken from the \
         orientations instead (keylo-eval `align_roll`).\n",
    );
    md
}

fn unique(items: impl Iterator<Item = String>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for i in items {
        if !out.contains(&i) {
            out.push(i);
        }
    }
    out
}

fn accuracy_cell(r: &Row) -> String {
    let poor = association::low(r)
        .map(|c| format!("only {} poses associated", c.ratio()))
        .or_else(|| degenerate_mark(r));
    if r.verdict != "ok" {
        return match poor {
            Some(p) => format!("N/A ({}; {p})", r.verdict),
            None => format!("N/A ({})", r.verdict),
        };
    }
    match (r.trans_mean_m, r.trans_rmse_m, r.rot_mean_deg, poor) {
        (Some(m), Some(s), Some(d), None) => format!("({m:.3}/{s:.3}, {d:.2})"),
        (Some(m), Some(s), Some(d), Some(p)) => format!("({m:.3}/{s:.3}, {d:.2}) ({p})"),
        (_, _, _, Some(p)) => format!("- ({p})"),
        _ => "- (no ground truth)".into(),
    }
}

/// `3 of 100 frames degenerate` for a run with degenerate frames.
fn degenerate_mark(r: &Row) -> Option<String> {
    let n = r.degenerate_frames.filter(|&n| n > 0)?;
    Some(match r.frames {
        Some(total) => format!("{n} of {total} frames degenerate"),
        None => format!("{n} frames degenerate"),
    })
}

/// The note under the tables naming the runs with degenerate frames, if any.
fn degenerate_note(rows: &[Row]) -> String {
    let marked: Vec<String> = rows
        .iter()
        .filter_map(|r| {
            Some(format!(
                "{} on {}: {}",
                r.variant,
                r.data,
                degenerate_mark(r)?
            ))
        })
        .collect();
    if marked.is_empty() {
        return String::new();
    }
    format!(
        "\n**Degenerate frames** (the registration could not constrain the pose: fewer \
         registered points than the registrar's minimum, or a direction without information; \
         their poses are, at least in part, the motion model's prediction; each run's \
         frames.csv flags them): {}.\n",
        marked.join("; ")
    )
}

fn find<'a>(rows: &'a [Row], variant: &str, data: &str) -> Option<&'a Row> {
    rows.iter().find(|r| r.variant == variant && r.data == data)
}

fn grid_table(
    rows: &[Row],
    variants: &[String],
    data: &[String],
    f: impl Fn(&Row) -> String,
) -> String {
    let mut md = format!("| configuration | {} |\n", data.join(" | "));
    md.push_str(&format!("|---|{}\n", "---|".repeat(data.len())));
    for v in variants {
        let cells: Vec<String> = data
            .iter()
            .map(|d| find(rows, v, d).map_or("(not run)".into(), &f))
            .collect();
        md.push_str(&format!("| {v} | {} |\n", cells.join(" | ")));
    }
    md
}

/// One line of the performance table: its name and how a run's cell is written.
type Indicator<'a> = (&'static str, Box<dyn Fn(&Row) -> String + 'a>);

fn performance(rows: &[Row], data: &str, variants: &[String]) -> String {
    let runs: Vec<&Row> = variants
        .iter()
        .filter_map(|v| find(rows, v, data))
        .collect();
    let head: Vec<String> = runs
        .iter()
        .map(|r| format!("{} ({})", r.variant, r.registrar))
        .collect();
    let mut md = format!("| indicator | {} |\n", head.join(" | "));
    md.push_str(&format!("|---|{}\n", "---|".repeat(runs.len())));
    let opt = |v: Option<f64>, d: usize| v.map_or("-".into(), |v| format!("{v:.d$}"));
    let lines: [Indicator<'_>; 8] = [
        (
            "Translation error (m), mean/RMSE",
            Box::new(
                |r| match (r.verdict.as_str(), r.trans_mean_m, r.trans_rmse_m) {
                    ("ok", Some(m), Some(s)) => format!("{m:.3}/{s:.3}"),
                    ("ok", _, _) => "-".into(),
                    _ => "N/A".into(),
                },
            ),
        ),
        (
            "Rotation error (deg), mean",
            Box::new(|r| match r.verdict.as_str() {
                "ok" => opt(r.rot_mean_deg, 2),
                _ => "N/A".into(),
            }),
        ),
        ("CPU (%)", Box::new(|r| opt(r.cpu_percent, 0))),
        ("Mem: peak RSS (MB)", Box::new(|r| opt(r.peak_rss_mb, 1))),
        ("Avg Pts", Box::new(|r| opt(r.mean_points, 0))),
        (
            "Odom rate (Hz, un-throttled)",
            Box::new(|r| opt(r.odometry_hz, 1)),
        ),
        ("Rate / raw cloud", Box::new(|r| opt(r.rate_vs_raw, 2))),
        (
            "Verdict",
            Box::new(|r| match degenerate_mark(r) {
                Some(m) if r.verdict == "ok" => format!("ok ({m})"),
                _ => r.verdict.clone(),
            }),
        ),
    ];
    for (name, f) in &lines {
        let cells: Vec<String> = runs.iter().map(|r| f(r)).collect();
        md.push_str(&format!("| {name} | {} |\n", cells.join(" | ")));
    }
    md
}

fn full_table(rows: &[Row]) -> String {
    let shown: Vec<_> = columns().filter(|c| c.0 != "config").collect();
    let mut md = format!(
        "| {} |\n|{}\n",
        shown.iter().map(|c| c.1).collect::<Vec<_>>().join(" | "),
        "---|".repeat(shown.len())
    );
    for v in as_values(rows) {
        let cells: Vec<String> = shown
            .iter()
            .map(|c| cell(&v, c.0, c.2).replace('|', "\\|"))
            .collect();
        md.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_comma_or_quote_in_a_field_round_trips() {
        let row = Row {
            data: "runs/a,b".into(),
            config: "say \"hi\", then go".into(),
            reason: "line one\nline two".into(),
            ..Row::default()
        };
        let text = csv(std::slice::from_ref(&row));
        let (header, records) = keylo::io::csv_table::parse(text.as_bytes()).unwrap();
        let field = |name: &str| {
            let i = header.iter().position(|h| h == name).unwrap();
            records[0][i].clone()
        };
        assert_eq!(records.len(), 1);
        assert_eq!(field("data"), row.data);
        assert_eq!(field("config"), row.config);
        assert_eq!(field("reason"), row.reason);
    }
}
