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

    fn binary(rows: &[u8]) -> Descriptors {
        Descriptors {
            rows: rows.len(),
            dim: 1,
            data: DescriptorData::Binary(rows.to_vec()),
        }
    }

    /// The nearest-row search is tested in `keylo_core::matching`; here, what these add:
    /// the order by distance, the kNN totals and the error for incompatible sets.
    #[test]
    fn matches_sorted_by_distance_and_knn_totals() {
        let q = binary(&[0b0000_0111, 0b1111_0000, 0b0000_0001]);
        let t = binary(&[0b0000_0000, 0b1111_0001]);
        let m = cross_checked(&q, &t, false).unwrap();
        let order: Vec<(usize, f32)> = m.iter().map(|m| (m.query, m.distance)).collect();
        // Distances 3, 1, 1: sorted, ties in query order.
        assert_eq!(order, vec![(1, 1.0), (2, 1.0), (0, 3.0)]);
        // Cross-checked: train 0's nearest is query 2, train 1's is query 1.
        let mutual: Vec<usize> = cross_checked(&q, &t, true)
            .unwrap()
            .iter()
            .map(|m| m.query)
            .collect();
        assert_eq!(mutual, vec![1, 2]);
        // kNN: every query row has two neighbours; 0.5 passes rows 1 (1 vs 4) and 2 (1 vs 4)
        // but not row 0 (3 vs 6).
        let (passed, total) = knn_ratio(&q, &t, 0.5).unwrap();
        assert_eq!(total, 3);
        assert_eq!(
            passed.iter().map(|m| m.query).collect::<Vec<_>>(),
            vec![1, 2]
        );
        // One train row: no pair has two neighbours, as OpenCV's knnMatch(k=2).
        assert_eq!(knn_ratio(&q, &binary(&[0]), 0.5).unwrap().1, 0);
        let float = Descriptors {
            rows: 1,
            dim: 1,
            data: DescriptorData::Float(vec![0.0]),
        };
        assert!(cross_checked(&q, &float, true).is_err());
        assert!(cross_checked(&q, &binary(&[]), true).unwrap().is_empty());
    }
}
