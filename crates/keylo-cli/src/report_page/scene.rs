//! The 3-D views of a report: point layers and polylines, thinned for the page and encoded
//! as base64 float32 for the page's script.

use serde::Serialize;

use super::html::base64;

/// One 3-D view.
#[derive(Debug, Serialize)]
pub struct Scene {
    pub title: String,
    pub clouds: Vec<Cloud>,
    pub lines: Vec<Polyline>,
}

/// A point layer: every `step`-th point of `total`.
#[derive(Debug, Serialize)]
pub struct Cloud {
    pub name: String,
    pub colour: String,
    /// Point size on screen, pixels.
    pub size: f32,
    pub total: usize,
    pub shown: usize,
    pub step: usize,
    /// x, y, z float32 little endian, base64.
    pub xyz: String,
}

/// A path through positions (a trajectory).
#[derive(Debug, Serialize)]
pub struct Polyline {
    pub name: String,
    pub colour: String,
    /// Size of the dot at each pose, pixels.
    pub size: f32,
    pub poses: usize,
    pub xyz: String,
}

impl Cloud {
    /// A layer of at most `max_points` of `points` (every k-th, in file order).
    pub fn thinned(name: &str, colour: &str, size: f32, points: &[[f32; 3]], max: usize) -> Self {
        let step = points.len().div_ceil(max.max(1)).max(1);
        let kept: Vec<[f32; 3]> = points.iter().step_by(step).copied().collect();
        Self {
            name: name.into(),
            colour: colour.into(),
            size,
            total: points.len(),
            shown: kept.len(),
            step,
            xyz: encode(&kept),
        }
    }

    /// "every 3rd of 412 345 points", or "412 345 points" when all are shown.
    pub fn describe(&self) -> String {
        if self.step == 1 {
            format!("{} points", self.total)
        } else {
            format!(
                "{} of {} points shown (one in {}: thinned for the page)",
                self.shown, self.total, self.step
            )
        }
    }
}

impl Polyline {
    /// A path with dots of `size` pixels (a reference drawn first with larger dots stays
    /// visible under an estimate that follows it closely).
    pub fn new(name: &str, colour: &str, size: f32, positions: &[[f32; 3]]) -> Self {
        Self {
            name: name.into(),
            colour: colour.into(),
            size,
            poses: positions.len(),
            xyz: encode(positions),
        }
    }
}

fn encode(points: &[[f32; 3]]) -> String {
    let bytes: Vec<u8> = points
        .iter()
        .flat_map(|p| p.iter().flat_map(|v| v.to_le_bytes()))
        .collect();
    base64(&bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_every_kth_point_and_says_so() {
        let pts: Vec<[f32; 3]> = (0..10).map(|i| [i as f32, 0.0, 0.0]).collect();
        let c = Cloud::thinned("map", "#fff", 2.0, &pts, 4);
        assert_eq!((c.step, c.shown, c.total), (3, 4, 10));
        assert!(c.describe().contains("4 of 10 points"));
        let all = Cloud::thinned("map", "#fff", 2.0, &pts, 100);
        assert_eq!((all.step, all.shown), (1, 10));
        assert_eq!(all.describe(), "10 points");
        // One point: 12 bytes, 16 base64 characters.
        assert_eq!(Polyline::new("p", "#000", 3.0, &pts[..1]).xyz.len(), 16);
    }
}
