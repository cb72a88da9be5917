//! Brute-force matching: Hamming distance for binary descriptors, L2 for float ones.

use keylo_core::{DescriptorData, Descriptors};
use opencv::core::{no_array, DMatch, Vector, NORM_HAMMING, NORM_L2};
use opencv::features2d::BFMatcher;
use opencv::prelude::*;

use crate::cv::descriptors_to_mat;
use crate::FeaturesError;

/// A match of query row `query` to train row `train`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Match {
    pub query: usize,
    pub train: usize,
    pub distance: f32,
}

fn matcher(
    query: &Descriptors,
    train: &Descriptors,
    cross_check: bool,
) -> Result<Option<opencv::core::Ptr<BFMatcher>>, FeaturesError> {
    if query.rows == 0 || train.rows == 0 {
        return Ok(None);
    }
    let same_kind = std::mem::discriminant(&query.data) == std::mem::discriminant(&train.data);
    if query.dim != train.dim || !same_kind {
        return Err(FeaturesError::BadInput(format!(
            "cannot match descriptors of {} and {} elements (or binary against float)",
            query.dim, train.dim
        )));
    }
    let norm = match query.data {
        DescriptorData::Binary(_) => NORM_HAMMING,
        DescriptorData::Float(_) => NORM_L2,
    };
    BFMatcher::create(norm, cross_check)
        .map(Some)
        .map_err(|e| FeaturesError::opencv("BFMatcher::create", e))
}

fn to_match(m: &DMatch) -> Option<Match> {
    Some(Match {
        query: usize::try_from(m.query_idx).ok()?,
        train: usize::try_from(m.train_idx).ok()?,
        distance: m.distance,
    })
}

/// Brute-force matches of every query row (best train row each), with OpenCV's cross-check
/// when `cross_check` (a pair is kept only when each is the other's best), sorted by distance.
pub fn cross_checked(
    query: &Descriptors,
    train: &Descriptors,
    cross_check: bool,
) -> Result<Vec<Match>, FeaturesError> {
    let Some(m) = matcher(query, train, cross_check)? else {
        return Ok(Vec::new());
    };
    let mut out = Vector::<DMatch>::new();
    m.train_match(
        &descriptors_to_mat(query)?,
        &descriptors_to_mat(train)?,
        &mut out,
        &no_array(),
    )
    .map_err(|e| FeaturesError::opencv("BFMatcher::match", e))?;
    let mut list: Vec<Match> = out.iter().filter_map(|d| to_match(&d)).collect();
    list.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    Ok(list)
}

/// kNN (k = 2) matches, without cross-check: `(passed, total)` where `passed` are the best
/// matches whose distance is below `ratio` × the second best's (Lowe's test) and `total` is
/// the number of query rows with two neighbours.
pub fn knn_ratio(
    query: &Descriptors,
    train: &Descriptors,
    ratio: f32,
) -> Result<(Vec<Match>, usize), FeaturesError> {
    let Some(m) = matcher(query, train, false)? else {
        return Ok((Vec::new(), 0));
    };
    let mut out = Vector::<Vector<DMatch>>::new();
    m.knn_train_match(
        &descriptors_to_mat(query)?,
        &descriptors_to_mat(train)?,
        &mut out,
        2,
        &no_array(),
        false,
    )
    .map_err(|e| FeaturesError::opencv("BFMatcher::knnMatch", e))?;
    let mut passed = Vec::new();
    let mut total = 0;
    for pair in out.iter() {
        let (Ok(a), Ok(b)) = (pair.get(0), pair.get(1)) else {
            continue;
        };
        total += 1;
        if a.distance < ratio * b.distance {
            passed.extend(to_match(&a));
        }
    }
    Ok((passed, total))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary(rows: &[[u8; 4]]) -> Descriptors {
        Descriptors {
            rows: rows.len(),
            dim: 4,
            data: DescriptorData::Binary(rows.iter().flatten().copied().collect()),
        }
    }

    #[test]
    fn cross_check_keeps_mutual_best_pairs() {
        let q = binary(&[[0, 0, 0, 0], [255, 255, 0, 0], [1, 0, 0, 0]]);
        let t = binary(&[[255, 255, 0, 1], [0, 0, 0, 0]]);
        let m = cross_checked(&q, &t, true).unwrap();
        // Row 2 also prefers train 1 but row 0 is closer: cross-check drops it.
        let pairs: Vec<(usize, usize)> = m.iter().map(|m| (m.query, m.train)).collect();
        assert_eq!(pairs, vec![(0, 1), (1, 0)]);
        assert_eq!(cross_checked(&q, &t, false).unwrap().len(), 3);
    }

    #[test]
    fn ratio_test_rejects_ambiguous_matches() {
        let q = binary(&[[0, 0, 0, 0], [15, 0, 0, 0]]);
        let t = binary(&[[0, 0, 0, 0], [255, 255, 255, 255], [3, 0, 0, 0]]);
        let (passed, total) = knn_ratio(&q, &t, 0.8).unwrap();
        assert_eq!(total, 2);
        // Row 0: 0 vs 2 bits → passes; row 1: 2 bits vs 4 bits → 2 < 3.2 passes too.
        assert_eq!(passed.len(), 2);
        let (passed, _) = knn_ratio(&q, &t, 0.4).unwrap();
        assert_eq!(passed.len(), 1);
    }

    #[test]
    fn empty_and_mismatched_sets() {
        let q = binary(&[[0, 0, 0, 0]]);
        let empty = Descriptors {
            rows: 0,
            dim: 0,
            data: DescriptorData::Binary(Vec::new()),
        };
        assert!(cross_checked(&q, &empty, true).unwrap().is_empty());
        let float = Descriptors {
            rows: 1,
            dim: 4,
            data: DescriptorData::Float(vec![0.0; 4]),
        };
        assert!(cross_checked(&q, &float, true).is_err());
    }
}
