//! Repeatability: the share of an image's keypoints that the transformed image finds again.

use std::collections::HashMap;

use keylo_core::Keypoint;

use crate::transforms::Homography;

/// Share of `original` keypoints whose position mapped by `h` has a keypoint of `transformed`
/// closer than `radius` pixels; `None` when `original` is empty. As the authors' code computes
/// it: the mapped position rounded to `f32` (OpenCV's `perspectiveTransform` on `Point2f`),
/// the distance of the `f32` difference, and strictly closer (a keypoint exactly `radius` away
/// — common with integer corner positions under the identity and the ×2 scaling — is not
/// found again).
pub fn repeatability(
    original: &[Keypoint],
    transformed: &[Keypoint],
    h: &Homography,
    radius: f64,
) -> Option<f64> {
    if original.is_empty() {
        return None;
    }
    let grid = Grid::new(transformed, radius);
    let repeated = original
        .iter()
        .filter(|k| {
            let (x, y) = h.map(f64::from(k.x), f64::from(k.y));
            grid.any_within(x, y, radius)
        })
        .count();
    Some(repeated as f64 / original.len() as f64)
}

/// Keypoints bucketed in square cells of the search radius: a query looks at 3×3 cells.
struct Grid {
    cell: f64,
    /// The keypoints' positions as they are (`f32`), by cell.
    cells: HashMap<(i64, i64), Vec<(f32, f32)>>,
}

impl Grid {
    fn new(points: &[Keypoint], radius: f64) -> Self {
        let mut cells: HashMap<(i64, i64), Vec<(f32, f32)>> = HashMap::new();
        for k in points {
            let (x, y) = (f64::from(k.x), f64::from(k.y));
            if x.is_finite() && y.is_finite() {
                cells
                    .entry(((x / radius).floor() as i64, (y / radius).floor() as i64))
                    .or_default()
                    .push((k.x, k.y));
            }
        }
        Self {
            cell: radius,
            cells,
        }
    }

    fn any_within(&self, x: f64, y: f64, radius: f64) -> bool {
        if !(x.is_finite() && y.is_finite()) {
            return false;
        }
        let (cx, cy) = (
            (x / self.cell).floor() as i64,
            (y / self.cell).floor() as i64,
        );
        let (qx, qy) = (x as f32, y as f32);
        (cx - 1..=cx + 1).any(|i| {
            (cy - 1..=cy + 1).any(|j| {
                self.cells.get(&(i, j)).is_some_and(|pts| {
                    pts.iter()
                        .any(|&(px, py)| closer_than(qx - px, qy - py, radius))
                })
            })
        })
    }
}

/// `cv::norm(Point2f(dx, dy)) < radius` as OpenCV evaluates it: the norm in `f64` of the `f32`
/// difference, stored as `f32`.
fn closer_than(dx: f32, dy: f32, radius: f64) -> bool {
    let norm = (f64::from(dx).powi(2) + f64::from(dy).powi(2)).sqrt() as f32;
    norm < radius as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kp(x: f32, y: f32) -> Keypoint {
        Keypoint {
            x,
            y,
            ..Keypoint::default()
        }
    }

    /// The same count by checking every pair.
    fn brute(original: &[Keypoint], transformed: &[Keypoint], h: &Homography, r: f64) -> f64 {
        let hit = original
            .iter()
            .filter(|k| {
                let (x, y) = h.map(f64::from(k.x), f64::from(k.y));
                let (x, y) = (x as f32, y as f32);
                transformed.iter().any(|t| closer_than(x - t.x, y - t.y, r))
            })
            .count();
        hit as f64 / original.len() as f64
    }

    #[test]
    fn counts_keypoints_found_again_within_the_radius() {
        let original = [kp(10.0, 10.0), kp(50.0, 20.0), kp(90.0, 5.0), kp(3.0, 3.0)];
        let shift = Homography([1.0, 0.0, 5.0, 0.0, 1.0, -2.0, 0.0, 0.0, 1.0]);
        // Found: the first two (within 4 px of the shifted position), not the others.
        let transformed = [kp(15.0, 8.0), kp(57.0, 19.0), kp(95.0 + 4.1, 3.0)];
        let r = repeatability(&original, &transformed, &shift, 4.0).unwrap();
        assert_eq!(r, 0.5);
        // Exactly 4 px away is not within 4 px (the authors' `min_dist < threshold`).
        let at_radius = [kp(15.0 + 4.0, 8.0)];
        assert_eq!(
            repeatability(&original[..1], &at_radius, &shift, 4.0),
            Some(0.0)
        );
        assert_eq!(repeatability(&[], &transformed, &shift, 4.0), None);
        assert_eq!(repeatability(&original, &[], &shift, 4.0), Some(0.0));
    }

    #[test]
    fn the_grid_agrees_with_checking_every_pair() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 33) % 10_000) as f32 / 10.0
        };
        let a: Vec<Keypoint> = (0..300).map(|_| kp(next(), next() / 10.0)).collect();
        let b: Vec<Keypoint> = (0..300).map(|_| kp(next(), next() / 10.0)).collect();
        let h = Homography([0.9, 0.1, 3.0, -0.1, 1.1, 2.0, 0.0, 0.0, 1.0]);
        for r in [1.0, 4.0, 9.5] {
            let got = repeatability(&a, &b, &h, r).unwrap();
            assert_eq!(got, brute(&a, &b, &h, r), "radius {r}");
        }
    }
}
