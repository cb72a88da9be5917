//! One image through one detector group: keypoints, the three robustness tests, then each
//! combination's descriptors and its matching against the previous image.

use std::time::Instant;

use keylo_core::{Descriptors, Image, Keypoint};
use keylo_features::matching::{cross_checked, homography_inliers, knn_ratio};

use crate::stages::{Describer, Group};
use crate::transforms::{blur, rotate, scale};
use crate::{
    repeatability, Definitions, KpEvalError, MetricParams, Row, ScalingHomography,
    SUPERPOINT_MATCH_DISTANCE,
};

/// What a combination keeps of the previous image.
#[derive(Default)]
pub struct Previous {
    features: Option<(Vec<Keypoint>, Descriptors)>,
}

/// The per-group state across images: one `Previous` per combination.
pub struct GroupState {
    pub previous: Vec<Previous>,
}

impl GroupState {
    pub fn new(group: &Group) -> Self {
        Self {
            previous: group.combos.iter().map(|_| Previous::default()).collect(),
        }
    }
}

fn ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// Detection-only figures of one image (shared by every combination of the detector).
struct Detection {
    keypoints: Vec<Keypoint>,
    detect_ms: f64,
    rotation: Option<f64>,
    scaling: Option<f64>,
    scaling_corrected: Option<f64>,
    blur: Option<f64>,
}

fn detect_all(
    group: &mut Group,
    image: &Image,
    p: &MetricParams,
) -> Result<Detection, KpEvalError> {
    let name = group.detector_name.clone();
    let err = |e| KpEvalError::stage(&name, "detector", e);
    let start = Instant::now();
    let keypoints = group.detector.detect(image).map_err(&err)?;
    let detect_ms = ms(start);
    let r = p.repeat_px;
    let defs = group.definitions;
    let rotated = rotate(image, p.rotation_deg, defs)?;
    let found = group.detector.detect(&rotated.image).map_err(&err)?;
    let rotation = repeatability(&keypoints, &found, &rotated.h, r);
    let paper_scaling = match defs {
        Definitions::Program => ScalingHomography::Paper,
        Definitions::SuperPointScript => ScalingHomography::Plain,
    };
    let scaled = scale(image, p.scale, paper_scaling)?;
    let corrected = crate::transforms::scaling_homography(
        ScalingHomography::Corrected,
        p.scale,
        image.width,
        image.height,
    );
    let found = group.detector.detect(&scaled.image).map_err(&err)?;
    let scaling = repeatability(&keypoints, &found, &scaled.h, r);
    let scaling_corrected = repeatability(&keypoints, &found, &corrected, r);
    let blurred = blur(image, p.blur_kernel, p.blur_sigma)?;
    let found = group.detector.detect(&blurred.image).map_err(&err)?;
    let blur = repeatability(&keypoints, &found, &blurred.h, r);
    Ok(Detection {
        keypoints,
        detect_ms,
        rotation,
        scaling,
        scaling_corrected,
        blur,
    })
}

/// Matching figures of a combination's image against its previous one.
struct Pairing {
    match_ms: f64,
    matches: usize,
    match_ratio: Option<f64>,
    inliers: usize,
    match_score: Option<f64>,
    knn_passed: usize,
    knn_total: usize,
}

fn pair(
    prev: &(Vec<Keypoint>, Descriptors),
    cur: &(Vec<Keypoint>, Descriptors),
    p: &MetricParams,
    defs: Definitions,
) -> Result<Pairing, KpEvalError> {
    let start = Instant::now();
    let mut matches = cross_checked(&prev.1, &cur.1, p.cross_check)?;
    let match_ms = ms(start);
    match defs {
        Definitions::SuperPointScript if p.max_match_distance == 0.0 => {
            matches.retain(|m| f64::from(m.distance) < SUPERPOINT_MATCH_DISTANCE);
        }
        _ if p.max_match_distance > 0.0 => {
            matches.retain(|m| f64::from(m.distance) <= p.max_match_distance);
        }
        _ => {}
    }
    let inliers = homography_inliers(&prev.0, &cur.0, &matches, p.ransac_px)?
        .iter()
        .filter(|b| **b)
        .count();
    // The C++ program queries with the previous image's descriptors, the SuperPoint script
    // with the current one's.
    let (query, train) = match defs {
        Definitions::Program => (&prev.1, &cur.1),
        Definitions::SuperPointScript => (&cur.1, &prev.1),
    };
    let (passed, knn_total) = knn_ratio(query, train, p.ratio as f32)?;
    let n = matches.len();
    Ok(Pairing {
        match_ms,
        matches: n,
        // Over the current image's described keypoints, as the authors' code divides
        // (`matches.size() / kPtsRef.size()`, the reference being the newer image).
        match_ratio: (!cur.0.is_empty()).then(|| n as f64 / cur.0.len() as f64),
        inliers,
        match_score: (n >= 4).then(|| inliers as f64 / n as f64),
        knn_passed: passed.len(),
        knn_total,
    })
}

/// Evaluates `image` (the `index`-th of its sequence) with every combination of `group`.
pub fn evaluate_image(
    group: &mut Group,
    state: &mut GroupState,
    image: &Image,
    (index, label): (usize, &str),
    interpolation: &str,
    p: &MetricParams,
) -> Result<Vec<Row>, KpEvalError> {
    let det = detect_all(group, image, p)?;
    let mut rows = Vec::with_capacity(group.combos.len());
    for (ci, (combo, describer)) in group.combos.iter_mut().enumerate() {
        let name = combo.name.as_str();
        let err = |stage: &'static str| move |e| KpEvalError::stage(name, stage, e);
        let start = Instant::now();
        let (keypoints, descriptors, detect_ms, describe_ms) = match describer {
            Describer::OwnPass => {
                let (kps, desc) = group
                    .detector
                    .detect_and_describe(image)
                    .map_err(err("detector"))?;
                let Some(desc) = desc else {
                    return Err(KpEvalError::Combo {
                        name: combo.name.clone(),
                        message: format!(
                            "detector `{}` returned no descriptors of its own: name a descriptor",
                            combo.detector
                        ),
                    });
                };
                // One pass: its time is the detection's, and describing adds nothing.
                (kps, desc, ms(start), 0.0)
            }
            Describer::Separate(d) => {
                let mut kps = det.keypoints.clone();
                let desc = if kps.is_empty() {
                    None
                } else {
                    Some(d.describe(image, &mut kps).map_err(err("descriptor"))?)
                };
                let desc = desc.unwrap_or(Descriptors {
                    rows: 0,
                    dim: 0,
                    data: keylo_core::DescriptorData::Binary(Vec::new()),
                });
                (kps, desc, det.detect_ms, ms(start))
            }
        };
        let current = (keypoints, descriptors);
        let pairing = match &state.previous[ci].features {
            Some(prev) => Some(pair(prev, &current, p, group.definitions)?),
            None => None,
        };
        rows.push(Row {
            index,
            label: label.to_string(),
            combo: combo.name.clone(),
            detector: combo.detector.clone(),
            descriptor: combo.descriptor.clone(),
            width: image.width,
            height: image.height,
            interpolation: interpolation.to_string(),
            keypoints: det.keypoints.len(),
            described: current.0.len(),
            robustness_rotation: det.rotation,
            robustness_scaling: det.scaling,
            robustness_scaling_corrected: det.scaling_corrected,
            robustness_blur: det.blur,
            detect_ms,
            describe_ms,
            match_ms: pairing.as_ref().map(|x| x.match_ms),
            time_ms: pairing
                .as_ref()
                .map(|x| detect_ms + describe_ms + x.match_ms),
            matches: pairing.as_ref().map(|x| x.matches),
            match_ratio: pairing.as_ref().and_then(|x| x.match_ratio),
            inliers: pairing.as_ref().map(|x| x.inliers),
            match_score: pairing.as_ref().and_then(|x| x.match_score),
            knn_passed: pairing.as_ref().map(|x| x.knn_passed),
            knn_total: pairing.as_ref().map(|x| x.knn_total),
            distinctiveness: pairing
                .as_ref()
                .and_then(|x| (x.knn_total > 0).then(|| x.knn_passed as f64 / x.knn_total as f64)),
        });
        state.previous[ci].features = Some(current);
    }
    Ok(rows)
}
