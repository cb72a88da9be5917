//! The reference trajectory of `keylo eval`, `compare` and `run --gt`: its clock
//! (`--gt-time-scale`, `--gt-time-offset`, applied when it is read), its name in tables and
//! plots (`--gt-label`), and the warning when few estimated poses associate with it.

use std::path::Path;

use anyhow::{Context, Result};
use clap::Args;
use keylo::eval::coverage::Coverage;
use keylo::eval::stamp_map::StampMap;
use keylo::io::trajectory::Format;

use crate::trajectories::Labelled;

/// How the reference's times are read and how it is named.
#[derive(Debug, Clone, Default, Args)]
pub struct ReferenceArgs {
    /// Multiply the reference's times by S when it is read: 0.1 for a reference that counts
    /// frames of a 10 Hz sensor, 1e-3 for milliseconds, 1e-9 for nanoseconds.
    #[arg(
        long,
        value_name = "S",
        value_parser = parse_scale,
        allow_negative_numbers = true
    )]
    pub gt_time_scale: Option<f64>,
    /// Then add SECONDS to the reference's times, e.g. to move a reference on Unix time to
    /// the estimate's time since the start (negative values allowed).
    #[arg(long, value_name = "SECONDS", value_parser = parse_offset, allow_negative_numbers = true)]
    pub gt_time_offset: Option<f64>,
    /// The reference's name in tables and plot legends (default: its file name).
    #[arg(long, value_name = "NAME")]
    pub gt_label: Option<String>,
}

impl ReferenceArgs {
    /// The reference's clock as given (identity without the options).
    pub fn stamp_map(&self) -> StampMap {
        StampMap {
            scale: self.gt_time_scale.unwrap_or(1.0),
            offset_s: self.gt_time_offset.unwrap_or(0.0),
        }
    }

    /// `--gt-label`, else the file name of `path`.
    pub fn label(&self, path: &Path) -> String {
        self.gt_label.clone().unwrap_or_else(|| file_label(path))
    }

    /// The reference at `path`, its clock mapped.
    pub fn read(&self, path: &Path) -> Result<Labelled> {
        read(path, self.stamp_map())
    }
}

/// The file name of `path` (`gt.tum`), or the whole path when it has none.
pub fn file_label(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    )
}

/// Reads the reference at `path` and maps its stamps with `map` (a KITTI file has none).
pub fn read(path: &Path, map: StampMap) -> Result<Labelled> {
    let mut gt = Labelled::read(path).with_context(|| format!("--gt {}", path.display()))?;
    if !map.is_identity() && gt.format == Format::Kitti {
        tracing::warn!(
            "{} has no time stamps (KITTI): --gt-time-scale/--gt-time-offset do not apply",
            gt.label
        );
    }
    map.apply(&mut gt.trajectory);
    Ok(gt)
}

/// The warning for a low `coverage` of the reference named `label`, read with `map`: the
/// figures, the likely cause and the options that undo it.
pub fn warning(coverage: &Coverage, label: &str, map: StampMap) -> String {
    let mut text = coverage.describe(label);
    if let Some(cause) = &coverage.likely_cause {
        text.push_str(&format!("; likely cause: {cause}"));
        if let Some(fix) = cause.fix() {
            text.push_str(&format!(": try {}", flags(map.then(&fix))));
        }
    }
    text
}

/// `--gt-time-scale S --gt-time-offset O`, each only when it changes the stamps.
fn flags(map: StampMap) -> String {
    let mut out = Vec::new();
    if map.scale != 1.0 {
        out.push(format!("--gt-time-scale {}", number(map.scale)));
    }
    if map.offset_s != 0.0 {
        out.push(format!("--gt-time-offset {}", number(map.offset_s)));
    }
    if out.is_empty() {
        return "no time options (they are what undoes it)".into();
    }
    out.join(" ")
}

/// A value as an option takes it: `0.1`, `1e-9`, `-1234.5`.
fn number(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-4 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn parse_scale(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err("expected a finite number > 0 (the factor on the reference's times)".into())
    }
}

fn parse_offset(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err("expected a finite number of seconds".into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_checked_and_flags_compose() {
        assert!(parse_scale("0").is_err() && parse_scale("-1").is_err());
        assert!(parse_scale("inf").is_err() && parse_scale("NaN").is_err());
        assert!(parse_offset("nan").is_err());
        assert_eq!(parse_scale("1e-9"), Ok(1e-9));
        assert_eq!(
            flags(StampMap::new(1e-9, -1234.5).unwrap()),
            "--gt-time-scale 1e-9 --gt-time-offset -1234.5"
        );
        assert_eq!(file_label(Path::new("a/b/gt.tum")), "gt.tum");
    }
}
