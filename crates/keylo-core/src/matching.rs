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
                hamming_row(&q[i * dim..(i + 1) * dim], t, row);
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

/// Bits that differ (over the shorter of the two), eight bytes at a time.
#[inline(always)]
pub fn hamming(a: &[u8], b: &[u8]) -> u32 {
    a.chunks_exact(8)
        .zip(b.chunks_exact(8))
        .map(|(x, y)| (word(x) ^ word(y)).count_ones())
        .sum::<u32>()
        + tail_bits(a, b)
}

/// Eight bytes as one word.
#[inline(always)]
fn word(bytes: &[u8]) -> u64 {
    u64::from_le_bytes(bytes.try_into().unwrap_or([0; 8]))
}

/// The Hamming distances of `a` to each `a.len()`-byte row of `train`, into `out`; with the
/// CPU's population-count instruction where it has one (the portable build counts bits in
/// software, several times slower).
fn hamming_row(a: &[u8], train: &[u8], out: &mut [f32]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("popcnt") {
        // SAFETY: the CPU has the `popcnt` instruction (checked just above).
        unsafe { hamming_row_popcnt(a, train, out) };
        return;
    }
    hamming_row_with(a, train, out);
}

/// [`hamming_row_with`] compiled with the `popcnt` instruction.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "popcnt")]
fn hamming_row_popcnt(a: &[u8], train: &[u8], out: &mut [f32]) {
    hamming_row_with(a, train, out);
}

/// [`hamming_row`] in whichever instruction set its caller is compiled for.
#[inline(always)]
fn hamming_row_with(a: &[u8], train: &[u8], out: &mut [f32]) {
    let dim = a.len();
    for (j, v) in out.iter_mut().enumerate() {
        *v = hamming(a, &train[j * dim..(j + 1) * dim]) as f32;
    }
}

/// Bits that differ in the bytes after the last whole eight-byte word.
#[inline(always)]
fn tail_bits(a: &[u8], b: &[u8]) -> u32 {
    let whole = a.len().min(b.len()) / 8 * 8;
    a[whole..]
        .iter()
        .zip(&b[whole..])
        .map(|(x, y)| (x ^ y).count_ones())
        .sum()
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

    /// The word-wise counts (with or without `popcnt`) equal a bit-by-bit count, for widths
    /// that are and are not whole words (ORB's 32 bytes, FREAK's 64, 61 and 3).
    #[test]
    fn word_wise_hamming_equals_counting_bits_one_by_one() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut byte = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 24) as u8
        };
        for dim in [3usize, 32, 61, 64] {
            let (rows, train_rows) = (5, 7);
            let q: Vec<u8> = (0..rows * dim).map(|_| byte()).collect();
            let t: Vec<u8> = (0..train_rows * dim).map(|_| byte()).collect();
            let bits = |a: &[u8], b: &[u8]| -> u32 {
                (0..a.len() * 8)
                    .map(|k| u32::from((a[k / 8] ^ b[k / 8]) >> (k % 8) & 1))
                    .sum()
            };
            let set = |v: &[u8], n| Descriptors {
                rows: n,
                dim,
                data: DescriptorData::Binary(v.to_vec()),
            };
            let d = distances(&set(&q, rows), &set(&t, train_rows));
            for i in 0..rows {
                for j in 0..train_rows {
                    let (a, b) = (&q[i * dim..(i + 1) * dim], &t[j * dim..(j + 1) * dim]);
                    assert_eq!(hamming(a, b), bits(a, b), "dim {dim}");
                    assert_eq!(d[i * train_rows + j], bits(a, b) as f32, "dim {dim}");
                    let mut one = [0.0f32];
                    hamming_row_with(a, b, &mut one);
                    assert_eq!(one[0], bits(a, b) as f32, "portable, dim {dim}");
                }
            }
        }
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
