//! Descriptor matching over keylo [`Descriptors`] (OpenCV's brute-force matcher and RANSAC
//! homography, so numbers agree with the paper's OpenCV-based metrics): cross-checked brute
//! force, kNN with Lowe's ratio test, and homography inliers.

mod brute_force;
mod homography;

pub use brute_force::{cross_checked, knn_ratio, Match};
pub use homography::homography_inliers;
