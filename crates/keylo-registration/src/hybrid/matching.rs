//! Brute-force descriptor matching between two frames, as OpenCV's `BFMatcher` (Hamming for
//! binary rows, L2 for float rows) with cross-check and Lowe's ratio test, in plain Rust so
//! the registrar needs no OpenCV. Ties go to the lower row: the result is deterministic.

use keylo_core::keypoints3d::well_formed;
use keylo_core::{DescriptorData, Descriptors};
use rayon::prelude::*;

/// Rows compared per parallel work item.
const CHUNK: usize = 64;

/// Pairs `(query row, train row)` whose best match passes the ratio test (best distance below
/// `ratio` × the second best; `ratio ≥ 1` turns it off) and, with `cross_check`, is mutual;
/// ascending by query row. Descriptor sets of different kinds or widths, or whose data is not
/// `rows × dim` long, give no pairs.
pub fn match_rows(
    query: &Descriptors,
    train: &Descriptors,
    ratio: f64,
    cross_check: bool,
) -> Vec<(usize, usize)> {
    let same_kind = std::mem::discriminant(&query.data) == std::mem::discriminant(&train.data);
    let usable = well_formed(query) && well_formed(train);
    if query.rows == 0 || train.rows == 0 || query.dim != train.dim || !same_kind || !usable {
        return Vec::new();
    }
    let d = distances(query, train);
    let m = train.rows;
    let best_of_train: Vec<usize> = if cross_check {
        (0..m)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|j| best_two((0..query.rows).map(|i| d[i * m + j])).0)
            .collect()
    } else {
        Vec::new()
    };
    (0..query.rows)
        .filter_map(|i| {
            let (best, first, second) = best_two(d[i * m..(i + 1) * m].iter().copied());
            let ratio_ok = ratio >= 1.0 || f64::from(first) < ratio * f64::from(second);
            let mutual = !cross_check || best_of_train[best] == i;
            (ratio_ok && mutual).then_some((i, best))
        })
        .collect()
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

/// Row-major `query.rows × train.rows` distances.
fn distances(query: &Descriptors, train: &Descriptors) -> Vec<f32> {
    let (n, m, dim) = (query.rows, train.rows, query.dim);
    let mut out = vec![0.0f32; n * m];
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

fn hamming(a: &[u8], b: &[u8]) -> u32 {
    a.iter().zip(b).map(|(x, y)| (x ^ y).count_ones()).sum()
}

fn l2(a: &[f32], b: &[f32]) -> f32 {
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
    fn cross_check_keeps_mutual_best_pairs() {
        // The case of keylo-features' OpenCV matcher test: the same pairs come out.
        let q = binary(&[[0, 0, 0, 0], [255, 255, 0, 0], [1, 0, 0, 0]]);
        let t = binary(&[[255, 255, 0, 1], [0, 0, 0, 0]]);
        assert_eq!(match_rows(&q, &t, 1.0, true), vec![(0, 1), (1, 0)]);
        assert_eq!(match_rows(&q, &t, 1.0, false).len(), 3);
    }

    #[test]
    fn ratio_test_rejects_ambiguous_matches() {
        let q = binary(&[[0, 0, 0, 0], [15, 0, 0, 0]]);
        let t = binary(&[[0, 0, 0, 0], [255, 255, 255, 255], [3, 0, 0, 0]]);
        assert_eq!(match_rows(&q, &t, 0.8, false).len(), 2);
        assert_eq!(match_rows(&q, &t, 0.4, false), vec![(0, 0)]);
    }

    #[test]
    fn float_rows_use_l2_and_mismatches_give_nothing() {
        let f = |v: &[f32]| Descriptors {
            rows: v.len() / 2,
            dim: 2,
            data: DescriptorData::Float(v.to_vec()),
        };
        let m = match_rows(
            &f(&[0.0, 0.0, 5.0, 5.0]),
            &f(&[5.1, 5.0, 0.1, 0.0]),
            0.8,
            true,
        );
        assert_eq!(m, vec![(0, 1), (1, 0)]);
        assert!(match_rows(&f(&[0.0, 0.0]), &binary(&[[0; 4]]), 0.8, true).is_empty());
        let short = Descriptors {
            rows: 2,
            dim: 2,
            data: DescriptorData::Float(vec![0.0; 3]),
        };
        assert!(match_rows(&short, &f(&[0.0, 0.0]), 0.8, true).is_empty());
    }
}
