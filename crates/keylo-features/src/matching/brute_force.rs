//! Brute-force matching for the keypoint evaluation and the matched windows: keylo's one
//! matcher ([`keylo_core::matching`]: Hamming distance for binary descriptors, L2 for float
//! ones, ties to the lower row, as OpenCV's `BFMatcher`).

use keylo_core::matching::{nearest, MatchError, Nearest};
use keylo_core::Descriptors;

use crate::FeaturesError;

/// A match of query row `query` to train row `train`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Match {
    pub query: usize,
    pub train: usize,
    pub distance: f32,
}

fn nearest_rows(
    query: &Descriptors,
    train: &Descriptors,
    cross_check: bool,
) -> Result<Vec<Nearest>, FeaturesError> {
    nearest(query, train, cross_check)
        .map_err(|e: MatchError| FeaturesError::BadInput(e.to_string()))
}

/// Brute-force matches of every query row (best train row each), cross-checked when
/// `cross_check` (a pair is kept only when each is the other's best, as OpenCV's
/// `BFMatcher(crossCheck=true).match`), sorted by distance (stably: query order on ties).
pub fn cross_checked(
    query: &Descriptors,
    train: &Descriptors,
    cross_check: bool,
) -> Result<Vec<Match>, FeaturesError> {
    let mut list: Vec<Match> = nearest_rows(query, train, cross_check)?
        .iter()
        .enumerate()
        .filter(|(_, n)| n.mutual)
        .map(|(query, n)| Match {
            query,
            train: n.train,
            distance: n.distance,
        })
        .collect();
    list.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    Ok(list)
}

/// kNN (k = 2) matches, without cross-check: `(passed, total)` where `passed` are the best
/// matches whose distance is below `ratio` × the second best's (Lowe's test) and `total` is
/// the number of query rows with two neighbours (all of them when the train set has two
/// rows or more, as OpenCV's `knnMatch(k=2)`).
pub fn knn_ratio(
    query: &Descriptors,
    train: &Descriptors,
    ratio: f32,
) -> Result<(Vec<Match>, usize), FeaturesError> {
    let list = nearest_rows(query, train, false)?;
    if train.rows < 2 {
        return Ok((Vec::new(), 0));
    }
    let passed = list
        .iter()
        .enumerate()
        .filter(|(_, n)| n.distance < ratio * n.second)
        .map(|(query, n)| Match {
            query,
            train: n.train,
            distance: n.distance,
        })
        .collect();
    Ok((passed, list.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::DescriptorData;

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
