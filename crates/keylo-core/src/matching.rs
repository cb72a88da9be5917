//! Brute-force descriptor matching, as OpenCV's `BFMatcher`: Hamming distance for binary rows,
//! L2 for float rows, every query row against every train row. The one matcher of keylo: the
//! `hybrid` registrar, the matched keypoint windows and the keypoint evaluation all use it.
//! Ties go to the lower row (as OpenCV's), so results are deterministic.
//!
//! ```
//! use keylo_core::matching::nearest;
//! use keylo_core::{DescriptorData, Descriptors};
//! let rows = |v: &[u8]| Descriptors { rows: v.len(), dim: 1, data: DescriptorData::Binary(v.to_vec()) };
//! let n = nearest(&rows(&[0b0000, 0b1111]), &rows(&[0b1110, 0b0001]), true).unwrap();
//! assert_eq!((n[0].train, n[0].distance, n[0].second), (1, 1.0, 3.0));
//! assert!(n[0].mutual && n[1].mutual);
//! ```

use rayon::prelude::*;

use crate::keypoints3d::well_formed;
use crate::{DescriptorData, Descriptors};

/// Rows compared per parallel work item.
const CHUNK: usize = 64;

/// The nearest train row of one query row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nearest {
    /// The nearest train row (the lowest of equally near ones).
    pub train: usize,
    /// Its distance.
    pub distance: f32,
    /// The second-nearest distance (∞ when the train set has one row): Lowe's ratio test
    /// compares the two.
    pub second: f32,
    /// Whether this query row is, in turn, the nearest query row of `train` (OpenCV's
    /// cross-check); `true` when not asked for.
    pub mutual: bool,
}

/// Why two descriptor sets cannot be matched.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MatchError {
    /// Different widths, or binary against float.
    #[error(
        "cannot match descriptors of {query_dim} and {train_dim} elements (or binary against float)"
    )]
    Incompatible { query_dim: usize, train_dim: usize },
    /// A set whose data is not `rows × dim` long.
    #[error("a descriptor set's data does not hold rows × dim elements")]
    Malformed,
}

/// The nearest train row of every query row (empty when either set is); with `mutual`, also
/// whether each pair is mutual.
pub fn nearest(
    query: &Descriptors,
    train: &Descriptors,
    mutual: bool,
) -> Result<Vec<Nearest>, MatchError> {
    if query.rows == 0 || train.rows == 0 {
        return Ok(Vec::new());
    }
    let same_kind = std::mem::discriminant(&query.data) == std::mem::discriminant(&train.data);
    if query.dim != train.dim || !same_kind {
        return Err(MatchError::Incompatible {
            query_dim: query.dim,
            train_dim: train.dim,
        });
    }
    if !well_formed(query) || !well_formed(train) {
        return Err(MatchError::Malformed);
    }
    let d = distances(query, train);
    let m = train.rows;
    let best_of_train: Vec<usize> = if mutual {
        (0..m)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|j| best_two((0..query.rows).map(|i| d[i * m + j])).0)
            .collect()
    } else {
        Vec::new()
    };
    Ok((0..query.rows)
        .map(|i| {
            let (best, first, second) = best_two(d[i * m..(i + 1) * m].iter().copied());
            Nearest {
                train: best,
                distance: first,
                second,
                mutual: !mutual || best_of_train[best] == i,
            }
        })
        .collect())
}

/// Index of the smallest value, the smallest and the second smallest (∞ with one value).
fn best_two(values: impl Iterator<Item = f32>) -> (usize, f32, f32) {
    let (mut best, mut first, mut second) = (0, f32::INFINITY, f32::INFINITY);
    for (i, v) in values.enumerate() {
        if v < first {
            (best, second, first) = (i, first, v);
        } else if v < second {
            second = v;
        }
    }
    (best, first, second)
}

/// Row-major `query.rows × train.rows` distances of two compatible, well-formed sets.
fn distances(query: &Descriptors, train: &Descriptors) -> Vec<f32> {
    let (m, dim) = (train.rows, query.dim);
    let mut out = vec![0.0f32; query.rows * m];
    out.par_chunks_mut(m)
        .with_min_len(CHUNK / 8)
        .enumerate()
        .for_each(|(i, row)| match (&query.data, &train.data) {
            (DescriptorData::Binary(q), DescriptorData::Binary(t)) => {
                let a = &q[i * dim..(i + 1) * dim];
                for (j, v) in row.iter_mut().enumerate() {
                    *v = hamming(a, &t[j * dim..(j + 1) * dim]) as f32;
                }
            }
            (DescriptorData::Float(q), DescriptorData::Float(t)) => {
                let a = &q[i * dim..(i + 1) * dim];
                for (j, v) in row.iter_mut().enumerate() {
                    *v = l2(a, &t[j * dim..(j + 1) * dim]);
                }
            }
            _ => row.fill(f32::INFINITY),
        });
    out
}

/// Bits that differ.
pub fn hamming(a: &[u8], b: &[u8]) -> u32 {
    a.iter().zip(b).map(|(x, y)| (x ^ y).count_ones()).sum()
}

/// Euclidean distance.
pub fn l2(a: &[f32], b: &[f32]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f32>()
        .sqrt()
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
    fn mutual_pairs_and_ties_to_the_lower_row() {
        let q = binary(&[[0, 0, 0, 0], [255, 255, 0, 0], [1, 0, 0, 0]]);
        let t = binary(&[[255, 255, 0, 1], [0, 0, 0, 0]]);
        let n = nearest(&q, &t, true).unwrap();
        let pairs: Vec<(usize, bool)> = n.iter().map(|n| (n.train, n.mutual)).collect();
        // Row 2 also prefers train 1, but row 0 is closer: not mutual.
        assert_eq!(pairs, vec![(1, true), (0, true), (1, false)]);
        assert!(nearest(&q, &t, false).unwrap().iter().all(|n| n.mutual));
        // Two equally near train rows: the lower wins, and the second distance equals it.
        let tie = nearest(
            &binary(&[[1, 0, 0, 0]]),
            &binary(&[[0; 4], [3, 0, 0, 0]]),
            false,
        );
        let tie = tie.unwrap()[0];
        assert_eq!((tie.train, tie.distance, tie.second), (0, 1.0, 1.0));
    }

    #[test]
    fn float_rows_use_l2_and_bad_sets_are_errors() {
        let f = |v: &[f32]| Descriptors {
            rows: v.len() / 2,
            dim: 2,
            data: DescriptorData::Float(v.to_vec()),
        };
        let n = nearest(&f(&[0.0, 0.0]), &f(&[3.0, 4.0, 30.0, 40.0]), false).unwrap();
        assert_eq!((n[0].train, n[0].distance, n[0].second), (0, 5.0, 50.0));
        assert_eq!(
            nearest(&f(&[0.0, 0.0]), &binary(&[[0; 4]]), true),
            Err(MatchError::Incompatible {
                query_dim: 2,
                train_dim: 4
            })
        );
        let short = Descriptors {
            rows: 2,
            dim: 2,
            data: DescriptorData::Float(vec![0.0; 3]),
        };
        assert_eq!(
            nearest(&short, &f(&[0.0, 0.0]), true),
            Err(MatchError::Malformed)
        );
        assert!(nearest(&f(&[]), &f(&[0.0, 0.0]), true).unwrap().is_empty());
    }
}
