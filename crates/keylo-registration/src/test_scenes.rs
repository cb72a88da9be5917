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

/// A closed 10 × 8 m room with floor and ceiling.
pub(crate) fn room() -> Vec<Point3<f64>> {
    let mut s = 5u64;
    (0..9000)
        .map(|_| {
            let (a, b) = (rnd(&mut s), rnd(&mut s));
            match (rnd(&mut s) * 6.0) as u32 {
                0 => Point3::new(a * 10.0 - 5.0, 4.0, b * 3.0 - 1.0),
                1 => Point3::new(a * 10.0 - 5.0, -4.0, b * 3.0 - 1.0),
                2 => Point3::new(5.0, a * 8.0 - 4.0, b * 3.0 - 1.0),
                3 => Point3::new(-5.0, a * 8.0 - 4.0, b * 3.0 - 1.0),
                4 => Point3::new(a * 10.0 - 5.0, b * 8.0 - 4.0, -1.0),
                _ => Point3::new(a * 10.0 - 5.0, b * 8.0 - 4.0, 2.0),
            }
        })
        .collect()
}
