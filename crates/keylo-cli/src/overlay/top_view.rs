//! A frame's points seen from above: every raw point in grey, the points the downsampler
//! gave the registrar in orange, range rings, the sensor in green. Forward (+x) is up, left
//! (+y) is left.

use nalgebra::Point3;

use super::canvas::{Canvas, Rgb};

/// Side of the square picture, pixels.
pub const SIDE: usize = 800;
pub const BACKGROUND: Rgb = [18, 18, 18];
pub const RAW: Rgb = [125, 125, 125];
pub const SELECTED: Rgb = [255, 130, 0];
const RING: Rgb = [60, 60, 60];
const SENSOR: Rgb = [40, 220, 90];

/// The picture and the distance (m) from its centre to its edge.
pub struct TopView {
    pub canvas: Canvas,
    pub half_extent_m: f64,
    pub ring_step_m: f64,
}

/// Draws `raw` and `selected` (sensor frame); the picture spans the distance of 95 % of the
/// raw points, rounded up to 5 m.
pub fn draw(raw: &[Point3<f64>], selected: &[Point3<f64>]) -> TopView {
    let half_extent_m = extent(raw);
    // 5 m rings, 10 m beyond a 40 m view, and at most about 12 rings however far it spans.
    let ring_step_m = match half_extent_m {
        e if e <= 40.0 => 5.0,
        e if e <= 120.0 => 10.0,
        e => (e / 12.0 / 10.0).ceil() * 10.0,
    };
    let centre = (SIDE / 2) as i64;
    let per_m = (SIDE / 2 - 1) as f64 / half_extent_m;
    // Far points (even absurd ones) land off the picture: saturating, never overflowing.
    let to_px = |p: &Point3<f64>| {
        (
            centre.saturating_sub((p.y * per_m).round() as i64),
            centre.saturating_sub((p.x * per_m).round() as i64),
        )
    };
    let mut canvas = Canvas::new(SIDE, SIDE, BACKGROUND);
    // Rings up to the picture's corners.
    let rings = (half_extent_m * 1.42 / ring_step_m) as usize;
    for k in 1..=rings {
        let r = k as f64 * ring_step_m;
        canvas.circle(centre, centre, (r * per_m).round() as i64, RING);
    }
    for p in raw
        .iter()
        .filter(|p| p.coords.iter().all(|v| v.is_finite()))
    {
        let (x, y) = to_px(p);
        canvas.set(x, y, RAW);
    }
    for p in selected
        .iter()
        .filter(|p| p.coords.iter().all(|v| v.is_finite()))
    {
        let (x, y) = to_px(p);
        canvas.dot(x, y, 1, SELECTED);
    }
    canvas.dot(centre, centre, 3, SENSOR);
    canvas.line((centre, centre), (centre, centre - 12), SENSOR);
    TopView {
        canvas,
        half_extent_m,
        ring_step_m,
    }
}

/// The horizontal distance of 95 % of the points, rounded up to a multiple of 5 m (at
/// least 5 m).
fn extent(points: &[Point3<f64>]) -> f64 {
    let mut d: Vec<f64> = points
        .iter()
        .map(|p| p.x.hypot(p.y))
        .filter(|d| d.is_finite())
        .collect();
    if d.is_empty() {
        return 5.0;
    }
    d.sort_by(f64::total_cmp);
    let k = ((d.len() - 1) as f64 * 0.95).round() as usize;
    ((d[k] / 5.0).ceil() * 5.0).max(5.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_land_forward_up_and_left_left() {
        let raw = [Point3::new(10.0, 0.0, 0.0), Point3::new(0.0, 10.0, 0.0)];
        let selected = [Point3::new(0.0, -10.0, 0.0)];
        let v = draw(&raw, &selected);
        assert_eq!(v.half_extent_m, 10.0);
        let c = &v.canvas;
        // 399 px per 10 m: 10 m ahead is the top edge's neighbour.
        assert_eq!(c.get(400, 1), Some(RAW));
        assert_eq!(c.get(1, 400), Some(RAW));
        assert_eq!(c.get(799, 400), Some(SELECTED));
        assert_eq!(c.get(400, 400), Some(SENSOR));
    }

    #[test]
    fn absurdly_far_points_keep_the_rings_few_and_land_off_the_picture() {
        let raw: Vec<Point3<f64>> = (0..100)
            .map(|i| Point3::new(1e15 * i as f64, -1e300, 0.0))
            .collect();
        let v = draw(&raw, &[Point3::new(f64::MAX, f64::MIN, 0.0)]);
        assert!(
            v.ring_step_m >= v.half_extent_m / 12.0,
            "{} m rings",
            v.ring_step_m
        );
        assert_eq!(v.canvas.get(400, 400), Some(SENSOR));
    }
}
