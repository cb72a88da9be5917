//! Descriptor matching between two frames for the keypoint terms: keylo's one brute-force
//! matcher ([`keylo_core::matching`], as OpenCV's `BFMatcher`) with cross-check and Lowe's
//! ratio test, in plain Rust so the registrar needs no OpenCV.

use keylo_core::matching::nearest;
use keylo_core::Descriptors;

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
    let Ok(list) = nearest(query, train, cross_check) else {
        return Vec::new();
    };
    list.iter()
        .enumerate()
        .filter(|(_, n)| {
            let ratio_ok = ratio >= 1.0 || f64::from(n.distance) < ratio * f64::from(n.second);
            ratio_ok && n.mutual
        })
        .map(|(i, n)| (i, n.train))
        .collect()
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
