//! keylo's per-image results held against the paper authors' own (`per-image/*.csv` of their
//! keypoint study: `image_number, evaluation_1, evaluation_2_1, …, evaluation_6`, one file per
//! combination): per combination, the images both have, the share with the same keypoint
//! count, and both medians of every metric over those images.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::stats::{combos_in_order, Metric, Quartiles, METRICS};
use crate::{KpEvalError, Row};

/// The authors' columns and the metric each holds (`evaluation_3`, time, is kept: it is shown,
/// never held to a goal, as it measures their machine).
const COLUMNS: [(&str, &str); 8] = [
    ("evaluation_1", "keypoints"),
    ("evaluation_2_1", "robustness_rotation"),
    ("evaluation_2_2", "robustness_scaling"),
    ("evaluation_2_3", "robustness_blur"),
    ("evaluation_3", "time_ms"),
    ("evaluation_4", "match_ratio"),
    ("evaluation_5", "match_score"),
    ("evaluation_6", "distinctiveness"),
];

/// Two values count as the same when they differ by less than this (the authors' CSVs hold
/// six significant digits).
pub const SAME: f64 = 5e-6;

/// The authors' results of one combination: per image number, the metric values.
#[derive(Debug, Clone, Default)]
pub struct ReferenceCombo {
    /// The file they came from.
    pub path: PathBuf,
    pub images: BTreeMap<u64, BTreeMap<&'static str, f64>>,
}

/// Every combination of a reference folder, by keylo's combination name.
#[derive(Debug, Clone, Default)]
pub struct Reference {
    pub combos: BTreeMap<String, ReferenceCombo>,
}

/// keylo's combination name for an authors' file stem: `AKAZE_AKAZE` as it is, their
/// `Superpoint` is `SUPERPOINT_SUPERPOINT`; `None` for runs keylo has no counterpart of
/// (`Superpoint_cuda`: the same network on a GPU).
fn combo_of(stem: &str) -> Option<String> {
    let upper = stem.to_ascii_uppercase();
    match upper.as_str() {
        "SUPERPOINT" => Some("SUPERPOINT_SUPERPOINT".into()),
        s if s.contains("CUDA") => None,
        s => Some(s.to_string()),
    }
}

impl Reference {
    /// Reads every `*.csv` of `dir`; a file whose header or numbers are not the authors'
    /// layout is an error that names it and the line.
    pub fn read_dir(dir: &Path) -> Result<Self, KpEvalError> {
        let entries = std::fs::read_dir(dir).map_err(|e| KpEvalError::io(dir, e))?;
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "csv"))
            .collect();
        paths.sort();
        let mut combos = BTreeMap::new();
        for path in paths {
            let stem = path
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
            if let Some(combo) = combo_of(&stem) {
                combos.insert(combo, read_csv(&path)?);
            }
        }
        if combos.is_empty() {
            return Err(KpEvalError::Format {
                path: dir.to_path_buf(),
                message: "no reference CSV (DETECTOR_DESCRIPTOR.csv with columns image_number, \
                          evaluation_1 … evaluation_6) in this folder"
                    .into(),
            });
        }
        Ok(Self { combos })
    }
}

fn read_csv(path: &Path) -> Result<ReferenceCombo, KpEvalError> {
    let (header, records) = keylo_io::csv_table::read(path).map_err(|e| KpEvalError::Format {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let bad = |line: usize, m: String| KpEvalError::Format {
        path: path.to_path_buf(),
        message: format!("line {line}: {m}"),
    };
    let at = |name: &str| header.iter().position(|h| h.trim() == name);
    let image_col = at("image_number").ok_or_else(|| {
        bad(
            1,
            "expected an `image_number` column (the authors' per-image layout)".into(),
        )
    })?;
    let cols: Vec<(usize, &'static str)> = COLUMNS
        .iter()
        .filter_map(|(name, key)| at(name).map(|i| (i, *key)))
        .collect();
    let mut images = BTreeMap::new();
    for (n, rec) in records.iter().enumerate() {
        let line = n + 2;
        let field = |i: usize| rec.get(i).map(|s| s.trim()).unwrap_or("");
        let image: u64 = field(image_col).parse().map_err(|_| {
            bad(
                line,
                format!(
                    "image_number {:?}: expected a whole number",
                    field(image_col)
                ),
            )
        })?;
        let mut values = BTreeMap::new();
        for &(i, key) in &cols {
            let text = field(i);
            if text.is_empty() || text.eq_ignore_ascii_case("nan") {
                continue;
            }
            let v: f64 = text
                .parse()
                .map_err(|_| bad(line, format!("{key} {text:?}: expected a number")))?;
            values.insert(key, v);
        }
        images.insert(image, values);
    }
    Ok(ReferenceCombo {
        path: path.to_path_buf(),
        images,
    })
}

/// The image number of a row: the last run of digits in its label (`image_0042.png` → 42),
/// else its index in the sequence.
pub fn image_number(row: &Row) -> u64 {
    let digits: String = row
        .label
        .rsplit(|c: char| !c.is_ascii_digit())
        .find(|s| !s.is_empty())
        .unwrap_or_default()
        .to_string();
    digits.parse().unwrap_or(row.index as u64)
}

/// One metric of one combination over the images both have.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetricAgreement {
    pub metric: &'static str,
    /// Images where both have a value.
    pub n: usize,
    pub ours_median: f64,
    pub theirs_median: f64,
    /// Share of those images where the values are the same (within [`SAME`]).
    pub same_share: f64,
}

/// keylo against the authors for one combination.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Agreement {
    pub combo: String,
    /// Images of ours that the reference also has.
    pub images: usize,
    /// Share of those with the same keypoint count.
    pub same_keypoints: f64,
    pub metrics: Vec<MetricAgreement>,
}

/// Every combination of `rows` that `reference` has, in the order of `rows`.
pub fn agreement(rows: &[Row], reference: &Reference) -> Vec<Agreement> {
    combos_in_order(rows)
        .into_iter()
        .filter_map(|combo| {
            let theirs = reference.combos.get(combo)?;
            let mine: Vec<(&Row, &BTreeMap<&str, f64>)> = rows
                .iter()
                .filter(|r| r.combo == combo)
                .filter_map(|r| theirs.images.get(&image_number(r)).map(|t| (r, t)))
                .collect();
            if mine.is_empty() {
                return None;
            }
            let metrics = METRICS
                .iter()
                .filter_map(|m| metric_agreement(m, &mine))
                .collect::<Vec<_>>();
            let same_keypoints = metrics
                .iter()
                .find(|a| a.metric == "keypoints")
                .map_or(0.0, |a| a.same_share);
            Some(Agreement {
                combo: combo.to_string(),
                images: mine.len(),
                same_keypoints,
                metrics,
            })
        })
        .collect()
}

fn metric_agreement(m: &Metric, pairs: &[(&Row, &BTreeMap<&str, f64>)]) -> Option<MetricAgreement> {
    let both: Vec<(f64, f64)> = pairs
        .iter()
        .filter_map(|(r, t)| Some((m.value(r)?, *t.get(m.key)?)))
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .collect();
    if both.is_empty() {
        return None;
    }
    let ours: Vec<f64> = both.iter().map(|p| p.0).collect();
    let theirs: Vec<f64> = both.iter().map(|p| p.1).collect();
    let same = both.iter().filter(|(a, b)| (a - b).abs() < SAME).count();
    Some(MetricAgreement {
        metric: m.key,
        n: both.len(),
        ours_median: Quartiles::of(&ours)?.median,
        theirs_median: Quartiles::of(&theirs)?.median,
        same_share: same as f64 / both.len() as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(label: &str, combo: &str, keypoints: usize, ratio: Option<f64>) -> Row {
        Row {
            label: label.into(),
            combo: combo.into(),
            keypoints,
            match_ratio: ratio,
            ..Row::default()
        }
    }

    #[test]
    fn rows_meet_the_authors_by_image_number() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("ORB_ORB.csv"),
            "image_number,evaluation_1,evaluation_2_1,evaluation_2_2,evaluation_2_3,evaluation_3,evaluation_4,evaluation_5,evaluation_6\n\
             1,10,0.5,0.1,0.4,3.2,0.8,0.9,0.7\n2,12,0.5,0.1,0.4,3.1,0.6,0.9,0.7\n",
        )
        .unwrap();
        std::fs::write(dir.path().join("Superpoint_cuda.csv"), "image_number\n1\n").unwrap();
        let reference = Reference::read_dir(dir.path()).unwrap();
        assert_eq!(reference.combos.keys().collect::<Vec<_>>(), ["ORB_ORB"]);
        let rows = [
            row("image_0000.png", "ORB_ORB", 9, None),
            row("image_0001.png", "ORB_ORB", 10, Some(0.8)),
            row("image_0002.png", "ORB_ORB", 11, Some(0.7)),
            row("image_0002.png", "FAST_BRIEF", 11, Some(0.7)),
        ];
        let a = agreement(&rows, &reference);
        assert_eq!(a.len(), 1);
        assert_eq!((a[0].images, a[0].same_keypoints), (2, 0.5));
        let ratio = a[0]
            .metrics
            .iter()
            .find(|m| m.metric == "match_ratio")
            .unwrap();
        assert_eq!((ratio.n, ratio.same_share), (2, 0.5));
        assert!((ratio.ours_median - 0.75).abs() < 1e-12);
        assert!((ratio.theirs_median - 0.7).abs() < 1e-12);
    }

    #[test]
    fn a_file_of_another_layout_names_itself_and_the_line() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("ORB_ORB.csv"),
            "image_number,evaluation_1\n1,ten\n",
        )
        .unwrap();
        let e = Reference::read_dir(dir.path()).unwrap_err().to_string();
        assert!(e.contains("ORB_ORB.csv") && e.contains("line 2"), "{e}");
        let empty = tempfile::tempdir().unwrap();
        let e = Reference::read_dir(empty.path()).unwrap_err().to_string();
        assert!(e.contains("no reference CSV"), "{e}");
    }
}
