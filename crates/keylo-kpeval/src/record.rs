//! One evaluated image of one combination: the per-image results (the authors' `per-image`
//! CSVs hold the same six metrics), written as CSV.

use serde::{Deserialize, Serialize};

/// The results of one image (metrics 1–3) and its pair with the previous image (4–6).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Row {
    /// Index of the image in the evaluated sequence (0: the first, which has no pair).
    pub index: usize,
    /// Frame index or file name.
    pub label: String,
    pub combo: String,
    pub detector: String,
    pub descriptor: String,
    pub width: usize,
    pub height: usize,
    pub interpolation: String,
    /// Metric 1: keypoints the detector found.
    pub keypoints: usize,
    /// Keypoints left after describing (descriptors may drop some near the border).
    pub described: usize,
    /// Metric 2_1: repeatability under the rotation.
    pub robustness_rotation: Option<f64>,
    /// Metric 2_2: repeatability under the scaling, with the authors' homography.
    pub robustness_scaling: Option<f64>,
    /// Repeatability under the scaling with the corrected homography (not in the paper).
    pub robustness_scaling_corrected: Option<f64>,
    /// Metric 2_3: repeatability under the Gaussian blur.
    pub robustness_blur: Option<f64>,
    pub detect_ms: f64,
    pub describe_ms: f64,
    /// Cross-checked brute-force matching with the previous image, ms.
    pub match_ms: Option<f64>,
    /// Metric 3: detect + describe + match, ms (from the second image on).
    pub time_ms: Option<f64>,
    /// Cross-checked matches with the previous image.
    pub matches: Option<usize>,
    /// Metric 4: matches / described keypoints of the previous image.
    pub match_ratio: Option<f64>,
    /// RANSAC homography inliers among the matches.
    pub inliers: Option<usize>,
    /// Metric 5: inliers / matches (none with fewer than 4 matches).
    pub match_score: Option<f64>,
    /// kNN (k = 2) matches passing the ratio test, and all kNN matches.
    pub knn_passed: Option<usize>,
    pub knn_total: Option<usize>,
    /// Metric 6: knn_passed / knn_total.
    pub distinctiveness: Option<f64>,
}

/// The CSV header (field order of [`Row`]).
pub const CSV_HEADER: &str = "index,label,combo,detector,descriptor,width,height,interpolation,\
keypoints,described,robustness_rotation,robustness_scaling,robustness_scaling_corrected,\
robustness_blur,detect_ms,describe_ms,match_ms,time_ms,matches,match_ratio,inliers,match_score,\
knn_passed,knn_total,distinctiveness";

fn opt<T: ToString>(v: &Option<T>) -> String {
    v.as_ref().map_or_else(String::new, ToString::to_string)
}

/// The columns of [`CSV_HEADER`].
pub fn csv_columns() -> impl Iterator<Item = &'static str> {
    CSV_HEADER.split(',')
}

impl Row {
    /// The row's CSV fields, in [`CSV_HEADER`] order (written, quoted where needed, by
    /// `keylo_io::csv_table`).
    pub fn record(&self) -> [String; 25] {
        [
            self.index.to_string(),
            self.label.clone(),
            self.combo.clone(),
            self.detector.clone(),
            self.descriptor.clone(),
            self.width.to_string(),
            self.height.to_string(),
            self.interpolation.clone(),
            self.keypoints.to_string(),
            self.described.to_string(),
            opt(&self.robustness_rotation),
            opt(&self.robustness_scaling),
            opt(&self.robustness_scaling_corrected),
            opt(&self.robustness_blur),
            format!("{:.4}", self.detect_ms),
            format!("{:.4}", self.describe_ms),
            self.match_ms
                .map_or_else(String::new, |v| format!("{v:.4}")),
            self.time_ms.map_or_else(String::new, |v| format!("{v:.4}")),
            opt(&self.matches),
            opt(&self.match_ratio),
            opt(&self.inliers),
            opt(&self.match_score),
            opt(&self.knn_passed),
            opt(&self.knn_total),
            opt(&self.distinctiveness),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_comma_in_a_field_round_trips_through_the_csv() {
        let row = Row {
            label: "a,b \"c\"".into(),
            combo: "FAST_BRIEF".into(),
            match_ratio: Some(0.5),
            ..Row::default()
        };
        let header: Vec<&str> = csv_columns().collect();
        assert_eq!(header.len(), row.record().len());
        let text = keylo_io::csv_table::table(&header, [row.record()]);
        let (read_header, records) = keylo_io::csv_table::parse(text.as_bytes()).unwrap();
        assert_eq!(read_header, header);
        assert_eq!(records, vec![row.record().to_vec()]);
        assert_eq!(records[0][1], "a,b \"c\"");
    }
}
