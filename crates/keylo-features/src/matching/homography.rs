//! RANSAC homography between matched keypoints (the paper's "match score").

use keylo_core::Keypoint;
use opencv::core::{Mat, Point2f, Vector};
use opencv::prelude::*;

use super::Match;
use crate::FeaturesError;

/// Which of `matches` (query keypoints → train keypoints) are inliers of the RANSAC
/// homography with reprojection threshold `threshold_px`; all false when fewer than 4
/// matches or no homography is found.
pub fn homography_inliers(
    query: &[Keypoint],
    train: &[Keypoint],
    matches: &[Match],
    threshold_px: f64,
) -> Result<Vec<bool>, FeaturesError> {
    if matches.len() < 4 {
        return Ok(vec![false; matches.len()]);
    }
    let point = |k: &Keypoint| Point2f::new(k.x, k.y);
    let mut src = Vector::<Point2f>::new();
    let mut dst = Vector::<Point2f>::new();
    for m in matches {
        let (Some(q), Some(t)) = (query.get(m.query), train.get(m.train)) else {
            return Err(FeaturesError::BadInput(format!(
                "match {} → {} indexes past {} query / {} train keypoints",
                m.query,
                m.train,
                query.len(),
                train.len()
            )));
        };
        src.push(point(q));
        dst.push(point(t));
    }
    let mut mask = Mat::default();
    let h = opencv::calib3d::find_homography(
        &src,
        &dst,
        &mut mask,
        opencv::calib3d::RANSAC,
        threshold_px,
    )
    .map_err(|e| FeaturesError::opencv("findHomography", e))?;
    if h.empty() || mask.rows() as usize != matches.len() {
        return Ok(vec![false; matches.len()]);
    }
    let bytes = crate::cv::mat_bytes(&mask)?;
    Ok(bytes.iter().map(|&b| b != 0).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kp(x: f32, y: f32) -> Keypoint {
        Keypoint {
            x,
            y,
            ..Keypoint::default()
        }
    }

    #[test]
    fn translation_inliers_and_an_outlier() {
        let query: Vec<Keypoint> = (0..10)
            .map(|i| kp(10.0 + 7.0 * i as f32, 5.0 + 3.0 * (i % 4) as f32))
            .collect();
        let mut train: Vec<Keypoint> = query.iter().map(|k| kp(k.x + 4.0, k.y - 1.0)).collect();
        train[9] = kp(300.0, 40.0);
        let matches: Vec<Match> = (0..10)
            .map(|i| Match {
                query: i,
                train: i,
                distance: 0.0,
            })
            .collect();
        let inliers = homography_inliers(&query, &train, &matches, 3.0).unwrap();
        assert_eq!(inliers.iter().filter(|b| **b).count(), 9);
        assert!(!inliers[9]);
        assert_eq!(
            homography_inliers(&query, &train, &matches[..3], 3.0).unwrap(),
            vec![false; 3]
        );
    }
}
