//! The distinct values of a scan's per-point times, and which one each point has.
//!
//! A spinning LiDAR fires a column of beams at once, so a scan of 131 072 points holds only its
//! 1 024 or 2 048 column times (a destaggered image too: each pixel keeps the time of the
//! column it was measured in). Deskewing then needs one SE(3) exponential per distinct time,
//! not per point, and gives bit-identical points: the same time gives the same transform.

/// Slots per distinct time allowed: the table stays at most a quarter full.
const LOAD: usize = 4;

/// The distinct times, in order of first appearance, and each point's index into them; `None`
/// when there are more than `limit` distinct times (per-point times of an unorganised cloud),
/// found as soon as the count passes it.
pub fn distinct_times(times: &[f64], limit: usize) -> Option<(Vec<f64>, Vec<u32>)> {
    let limit = limit.min(u32::MAX as usize);
    let slots = (limit.max(1) * LOAD).next_power_of_two();
    let shift = u64::BITS - slots.trailing_zeros();
    // Each slot holds (time bits, index + 1); 0 marks an empty slot.
    let mut table = vec![(0u64, 0u32); slots];
    let mut values = Vec::new();
    let mut index = Vec::with_capacity(times.len());
    for &t in times {
        let bits = t.to_bits();
        let mut slot = slot_of(bits, shift);
        loop {
            let (key, id) = table[slot];
            if id == 0 {
                if values.len() == limit {
                    return None;
                }
                values.push(t);
                table[slot] = (bits, values.len() as u32);
                index.push(values.len() as u32 - 1);
                break;
            }
            if key == bits {
                index.push(id - 1);
                break;
            }
            slot = (slot + 1) & (slots - 1);
        }
    }
    Some((values, index))
}

/// Fibonacci hashing of the bits to a slot (`shift` = 64 − log2(slots), below 64: a table
/// has at least `LOAD` slots).
fn slot_of(bits: u64, shift: u32) -> usize {
    (bits.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> shift) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_times_repeat_over_rows() {
        // 4 rows of 8 columns, row-major: 8 distinct times.
        let times: Vec<f64> = (0..32).map(|i| f64::from(i % 8) * 1e-4 + 1.7e9).collect();
        let (values, index) = distinct_times(&times, 100).unwrap();
        assert_eq!(values.len(), 8);
        for (t, &i) in times.iter().zip(&index) {
            assert_eq!(values[i as usize].to_bits(), t.to_bits());
        }
    }

    #[test]
    fn too_many_distinct_times_give_none() {
        let times: Vec<f64> = (0..100).map(f64::from).collect();
        assert!(distinct_times(&times, 99).is_none());
        assert_eq!(distinct_times(&times, 100).unwrap().0.len(), 100);
    }

    #[test]
    fn zero_nan_and_a_limit_of_one() {
        let times = [0.0, f64::NAN, 0.0, -0.0];
        let (values, index) = distinct_times(&times, 3).unwrap();
        assert_eq!(values.len(), 3, "0.0, NaN and -0.0 have distinct bits");
        assert_eq!(index, vec![0, 1, 0, 2]);
        assert_eq!(distinct_times(&[2.5; 10], 1).unwrap().0, vec![2.5]);
        assert!(distinct_times(&[], 1).unwrap().0.is_empty());
    }
}
