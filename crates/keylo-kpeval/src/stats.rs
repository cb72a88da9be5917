//! Per-combination distributions of every metric: quartiles (as numpy's default linear
//! percentile, the paper's box plots) and mean.

use serde::Serialize;

use crate::Row;

/// A metric of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Metric {
    /// Column name in the CSV / JSON.
    pub key: &'static str,
    /// The paper's figure id (`1_Keypoints_number`, …), empty for keylo's extra metric.
    pub paper_figure: &'static str,
    /// Axis label.
    pub label: &'static str,
    /// Larger is better (for picking optima).
    pub higher_is_better: bool,
    /// The figure depends on the detector only (the same for all its combinations).
    pub per_detector: bool,
}

/// Every metric, in the paper's order (keylo's corrected scaling after the paper's).
pub const METRICS: &[Metric] = &[
    Metric {
        key: "keypoints",
        paper_figure: "1_Keypoints_number",
        label: "keypoints",
        higher_is_better: true,
        per_detector: true,
    },
    Metric {
        key: "robustness_rotation",
        paper_figure: "2_1_Robustness_rotated",
        label: "robustness to rotation",
        higher_is_better: true,
        per_detector: true,
    },
    Metric {
        key: "robustness_scaling",
        paper_figure: "2_2_Robustness_scaling",
        label: "robustness to scaling (paper's homography)",
        higher_is_better: true,
        per_detector: true,
    },
    Metric {
        key: "robustness_scaling_corrected",
        paper_figure: "",
        label: "robustness to scaling (corrected homography)",
        higher_is_better: true,
        per_detector: true,
    },
    Metric {
        key: "robustness_blur",
        paper_figure: "2_3_Robustness_blurred",
        label: "robustness to blur",
        higher_is_better: true,
        per_detector: true,
    },
    Metric {
        key: "time_ms",
        paper_figure: "3_Computational_efficiency",
        label: "detect + describe + match, ms",
        higher_is_better: false,
        per_detector: false,
    },
    Metric {
        key: "match_ratio",
        paper_figure: "4_Match_Ratio",
        label: "match ratio",
        higher_is_better: true,
        per_detector: false,
    },
    Metric {
        key: "match_score",
        paper_figure: "5_Match_Score",
        label: "match score",
        higher_is_better: true,
        per_detector: false,
    },
    Metric {
        key: "distinctiveness",
        paper_figure: "6_Distinctiveness",
        label: "distinctiveness",
        higher_is_better: true,
        per_detector: false,
    },
];

impl Metric {
    /// The metric's value in `row`, if it has one.
    pub fn value(&self, row: &Row) -> Option<f64> {
        match self.key {
            "keypoints" => Some(row.keypoints as f64),
            "robustness_rotation" => row.robustness_rotation,
            "robustness_scaling" => row.robustness_scaling,
            "robustness_scaling_corrected" => row.robustness_scaling_corrected,
            "robustness_blur" => row.robustness_blur,
            "time_ms" => row.time_ms,
            "match_ratio" => row.match_ratio,
            "match_score" => row.match_score,
            "distinctiveness" => row.distinctiveness,
            _ => None,
        }
    }

    /// The metric called `key`.
    pub fn by_key(key: &str) -> Option<&'static Metric> {
        METRICS.iter().find(|m| m.key == key)
    }
}

/// The spread of one metric over the images of one combination.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quartiles {
    pub n: usize,
    pub min: f64,
    pub q1: f64,
    pub median: f64,
    pub q3: f64,
    pub max: f64,
    pub mean: f64,
}

impl Quartiles {
    /// Quartiles of the finite `values`; `None` when there are none.
    pub fn of(values: &[f64]) -> Option<Self> {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| {
            let pos = q * (v.len() - 1) as f64;
            let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
            v[lo] + (v[hi] - v[lo]) * (pos - lo as f64)
        };
        Some(Self {
            n: v.len(),
            min: v[0],
            q1: at(0.25),
            median: at(0.5),
            q3: at(0.75),
            max: v[v.len() - 1],
            mean: v.iter().sum::<f64>() / v.len() as f64,
        })
    }
}

/// Every metric's spread for one combination.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ComboSummary {
    pub combo: String,
    pub detector: String,
    pub descriptor: String,
    pub images: usize,
    /// `(metric key, its quartiles)` in [`METRICS`] order; a metric without values is absent.
    pub metrics: Vec<(String, Quartiles)>,
}

impl ComboSummary {
    /// The quartiles of metric `key`.
    pub fn get(&self, key: &str) -> Option<&Quartiles> {
        self.metrics.iter().find(|(k, _)| k == key).map(|(_, q)| q)
    }
}

/// The combinations of `rows`, each once, in order of first appearance.
pub(crate) fn combos_in_order(rows: &[Row]) -> Vec<&str> {
    let mut order: Vec<&str> = Vec::new();
    for r in rows {
        if !order.contains(&r.combo.as_str()) {
            order.push(&r.combo);
        }
    }
    order
}

/// One summary per combination of `rows`, in order of first appearance.
pub fn summarise(rows: &[Row]) -> Vec<ComboSummary> {
    combos_in_order(rows)
        .into_iter()
        .map(|combo| {
            let mine: Vec<&Row> = rows.iter().filter(|r| r.combo == combo).collect();
            let metrics = METRICS
                .iter()
                .filter_map(|m| {
                    let values: Vec<f64> = mine.iter().filter_map(|r| m.value(r)).collect();
                    Quartiles::of(&values).map(|q| (m.key.to_string(), q))
                })
                .collect();
            ComboSummary {
                combo: combo.to_string(),
                detector: mine
                    .first()
                    .map_or_else(String::new, |r| r.detector.clone()),
                descriptor: mine
                    .first()
                    .map_or_else(String::new, |r| r.descriptor.clone()),
                images: mine.len(),
                metrics,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quartiles_are_numpys_linear_percentiles() {
        // numpy.percentile([1, 2, 3, 4, 10], [25, 50, 75]) = [2, 3, 4]
        let q = Quartiles::of(&[10.0, 1.0, 3.0, 2.0, 4.0, f64::NAN]).unwrap();
        assert_eq!((q.q1, q.median, q.q3), (2.0, 3.0, 4.0));
        assert_eq!((q.n, q.min, q.max, q.mean), (5, 1.0, 10.0, 4.0));
        // numpy.percentile([1, 2, 3, 4], [25, 50, 75]) = [1.75, 2.5, 3.25]
        let q = Quartiles::of(&[1.0, 2.0, 3.0, 4.0]).unwrap();
        assert_eq!((q.q1, q.median, q.q3), (1.75, 2.5, 3.25));
        assert!(Quartiles::of(&[]).is_none());
    }

    #[test]
    fn summaries_per_combination_skip_missing_values() {
        let row = |combo: &str, kp: usize, ratio: Option<f64>| Row {
            combo: combo.into(),
            keypoints: kp,
            match_ratio: ratio,
            ..Row::default()
        };
        let rows = [
            row("A", 10, None),
            row("B", 5, None),
            row("A", 20, Some(0.5)),
            row("A", 30, Some(0.7)),
        ];
        let s = summarise(&rows);
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].combo, "A");
        assert_eq!(s[0].images, 3);
        assert_eq!(s[0].get("keypoints").unwrap().median, 20.0);
        assert_eq!(s[0].get("match_ratio").unwrap().n, 2);
        assert!(s[1].get("match_ratio").is_none());
    }
}
