//! How many of a run's poses were paired with ground truth, and the warning when fewer than
//! 90 % were: in the row (`associated`, the reason of its verdict), once per data set on
//! stderr, and under compare.md's tables.

use keylo::eval::associate::AssociateOptions;
use keylo::eval::coverage::{of_pairing, Coverage};
use keylo::Trajectory;

use super::row::{Criterion, Row};
use super::schedule::Planned;

/// Fills the row's `associated`, `association` and `association_warning` for `est` paired
/// with `gt` as the APE pairs them.
pub fn measure(plan: &Planned, est: &Trajectory, gt: &Trajectory, crit: &Criterion, row: &mut Row) {
    let opts = AssociateOptions {
        max_diff: crit.t_max_diff_s,
        ..AssociateOptions::default()
    };
    let coverage = of_pairing(est, gt, &opts);
    row.associated = Some(coverage.ratio());
    if coverage.is_low() {
        row.association_warning = Some(crate::reference_args::warning(
            &coverage,
            &reference(row),
            plan.gt_time.unwrap_or_default(),
        ));
    }
    row.association = Some(coverage);
}

/// The ground truth's name in a row's messages.
fn reference(row: &Row) -> String {
    row.reference
        .clone()
        .unwrap_or_else(|| "the ground truth".into())
}

/// The coverage of a row when it is low.
pub fn low(row: &Row) -> Option<&Coverage> {
    row.association.as_ref().filter(|c| c.is_low())
}

/// The reason of a verdict, saying so when few poses were paired: a run diverged by poor
/// association must not read as plainly diverged.
pub fn explain(row: &Row, verdict: &str, reason: String) -> String {
    let Some(c) = low(row) else { return reason };
    let cause = c
        .likely_cause
        .map_or(String::new(), |cause| format!(": {cause}"));
    let paired = format!("{} poses paired with {}", c.ratio(), reference(row));
    match verdict {
        "diverged" => format!("poor association (only {paired}{cause}); on those: {reason}"),
        "ok" => format!("{reason}; poor association: only {paired}{cause}"),
        _ => reason,
    }
}

/// One warning per data set (its first run with a low coverage): (data, text).
pub fn warnings(rows: &[Row]) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = Vec::new();
    for r in rows {
        if let Some(w) = &r.association_warning {
            if !out.iter().any(|(d, _)| *d == r.data) {
                out.push((r.data.clone(), w.clone()));
            }
        }
    }
    out
}

/// The warnings as Markdown lines under a table (empty without any).
pub fn markdown(rows: &[Row]) -> String {
    warnings(rows)
        .iter()
        .map(|(data, text)| format!("\n**Warning ({data}):** {text}.\n"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo::eval::coverage::coverage;

    #[test]
    fn a_diverged_run_says_it_was_poorly_associated() {
        let est: Vec<f64> = (0..154).map(|i| i as f64 * 0.1).collect();
        let frames: Vec<f64> = (0..154).map(f64::from).collect();
        let row = Row {
            data: "seq".into(),
            reference: Some("ref.tum".into()),
            association: Some(coverage(&est, &frames, 16, 0.01)),
            association_warning: Some("w".into()),
            ..Row::default()
        };
        let why = explain(&row, "diverged", "max APE 3.00 m > 2 m".into());
        assert!(
            why.starts_with("poor association (only 16/154 poses paired with ref.tum: ")
                && why.ends_with("; on those: max APE 3.00 m > 2 m"),
            "{why}"
        );
        assert_eq!(warnings(&[row.clone(), row]).len(), 1);
    }
}
