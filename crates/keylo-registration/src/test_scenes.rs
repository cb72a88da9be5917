//! Synthetic point sets shared by the unit tests.

use nalgebra::Point3;

/// A uniform number in [0, 1) from a 64-bit LCG.
pub(crate) fn rnd(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// `n` points on a corridor along x, `length` m long and centred on 0: two walls at y = ±2
/// and a floor at z = −1.
pub(crate) fn corridor(seed: u64, n: usize, length: f64) -> Vec<Point3<f64>> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            let (x, b) = (rnd(&mut s) * length - length / 2.0, rnd(&mut s));
            match (rnd(&mut s) * 3.0) as u32 {
                0 => Point3::new(x, 2.0, b * 3.0 - 1.0),
                1 => Point3::new(x, -2.0, b * 3.0 - 1.0),
                _ => Point3::new(x, b * 4.0 - 2.0, -1.0),
            }
        })
        .collect()
}
