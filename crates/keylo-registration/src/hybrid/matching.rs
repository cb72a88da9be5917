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

    fn binary(rows: &[u8]) -> Descriptors {
        Descriptors {
            rows: rows.len(),
            dim: 1,
            data: DescriptorData::Binary(rows.to_vec()),
        }
    }

    /// The nearest-row search itself is tested in `keylo_core::matching`; here, the filters.
    #[test]
    fn ratio_and_cross_check_filter_the_nearest_rows() {
        let q = binary(&[0b0000_0000, 0b0000_1111, 0b0000_0001]);
        let t = binary(&[0b0000_0000, 0b0000_0111, 0b1111_1111]);
        // Row 2 (1 bit from train 0, 2 from train 1) is not mutual: row 0 is train 0's own.
        assert_eq!(match_rows(&q, &t, 1.0, true), vec![(0, 0), (1, 1)]);
        assert_eq!(match_rows(&q, &t, 1.0, false).len(), 3);
        // Ratio 0.4: row 1 (1 bit vs 4) passes, row 2 (1 vs 2) does not.
        assert_eq!(match_rows(&q, &t, 0.4, false), vec![(0, 0), (1, 1)]);
        // Sets that cannot be matched give no pair (the registrar goes on without them).
        let float = Descriptors {
            rows: 1,
            dim: 1,
            data: DescriptorData::Float(vec![0.0]),
        };
        assert!(match_rows(&q, &float, 0.8, true).is_empty());
    }
}
