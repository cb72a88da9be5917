//! The paper's matching metrics on two consecutive real Ouster frames.

mod common;

use keylo_core::Registry;
use keylo_features::matching::{cross_checked, homography_inliers, knn_ratio};

#[test]
fn consecutive_real_frames_match_under_a_homography() {
    let frames = common::os0_frames();
    let mut registry = Registry::default();
    keylo_features::register(&mut registry);
    let f = registry.detectors.get("orb").unwrap();
    let mut orb = f
        .build(
            &f.resolve(&"describe = true".parse().unwrap()).unwrap(),
            &Default::default(),
        )
        .unwrap();
    let a = common::signal_image(&frames[0]);
    let b = common::signal_image(&frames[1]);
    let (ka, da) = orb.detect_and_describe(&a).unwrap();
    let (kb, db) = orb.detect_and_describe(&b).unwrap();
    let (da, db) = (da.unwrap(), db.unwrap());
    // Match ratio: cross-checked matches / keypoints of the previous frame.
    let matches = cross_checked(&db, &da, true).unwrap();
    let ratio = matches.len() as f64 / ka.len() as f64;
    // Match score: RANSAC homography inliers (3 px) / matches.
    let inliers = homography_inliers(&kb, &ka, &matches, 3.0).unwrap();
    let score = inliers.iter().filter(|i| **i).count() as f64 / matches.len() as f64;
    let (passed, total) = knn_ratio(&db, &da, 0.8).unwrap();
    assert!(ratio > 0.3 && ratio <= 1.0, "match ratio {ratio}");
    assert!(score > 0.3, "match score {score}");
    assert!(total > 0 && !passed.is_empty() && passed.len() <= total);
}
