//! keylo's keypoint evaluation suite: the six metrics of the paper's keypoint study (its
//! Section IV-A and Algorithm 2) for any detector/descriptor combination a [`Registry`]
//! knows — built-in or plugin — and its preprocessing sweep (Algorithm 1: interpolation ×
//! width × height).
//!
//! Every definition follows the authors' code (see `docs/keypoint-eval.md`):
//! 1. number of keypoints;
//! 2. robustness (repeatability) to a 45° rotation on an enlarged canvas, a ×2 scaling and a
//!    5×5 Gaussian blur: the share of keypoints whose position mapped by the transform's
//!    homography has a keypoint of the transformed image within 4 px — with the authors'
//!    scaling homography and, as a separate metric, the corrected one;
//! 3. time of detect + describe + match, ms;
//! 4. match ratio: cross-checked brute-force matches with the previous frame / its keypoints;
//! 5. match score: RANSAC homography inliers (3 px) / matches;
//! 6. distinctiveness: kNN (k = 2) matches passing Lowe's ratio 0.8 / all kNN matches.
//!
//! [`Registry`]: keylo_core::Registry

mod combos;
mod error;
mod frame_eval;
pub mod items;
pub mod motion;
mod params;
pub mod pictures;
mod plane;
pub mod realism;
mod record;
pub mod reference;
mod repeat;
mod runner;
mod spec;
mod stages;
mod stats;
pub mod sweep;
mod transforms;

pub use combos::{parse_combos, Combo, ComboSet};
pub use error::KpEvalError;
pub use params::{Definitions, MetricParams, ScalingHomography, SUPERPOINT_MATCH_DISTANCE};
pub use plane::Plane;
pub use record::{csv_columns, Row, CSV_HEADER};
pub use repeat::repeatability;
pub use runner::{evaluate, EvalOptions, GroupOutcome};
pub use spec::{EvalSpec, ImageSpec, Preset};
pub use stats::{summarise, ComboSummary, Metric, Quartiles, METRICS};
pub use transforms::{blur, rotate, scale, Transformed};
