//! A local frame along a scene's path (its centre line), for placing things beside it.

use nalgebra::Vector2;

use super::SceneBuilder;
use crate::motion::Motion;
use crate::texture::Material;
use crate::world::Object;

/// A frame along the path: point, unit tangent, unit left normal.
pub(super) struct PathFrame {
    p: Vector2<f64>,
    t: Vector2<f64>,
    n: Vector2<f64>,
}

impl PathFrame {
    /// The frame `s` metres along `motion`'s path.
    pub fn at(motion: &Motion, s: f64) -> Self {
        let p = motion.position_at_distance(s);
        let d = motion.position_at_distance(s + 0.5) - motion.position_at_distance(s - 0.5);
        let t = d.try_normalize(1e-12).unwrap_or(Vector2::x());
        Self {
            p,
            t,
            n: Vector2::new(-t.y, t.x),
        }
    }

    /// World point `along` metres ahead and `lateral` metres to the left.
    pub fn offset(&self, along: f64, lateral: f64) -> [f32; 2] {
        let q = self.p + self.t * along + self.n * lateral;
        [q.x as f32, q.y as f32]
    }

    /// Heading of the path, radians.
    pub fn yaw(&self) -> f32 {
        self.t.y.atan2(self.t.x) as f32
    }
}

/// How to pave a path: slabs about `length` metres long (overlapping by `overlap` at each end),
/// `half_width` to either side of the centre line, 0.1 m thick with their centre at `z`.
pub(super) struct Paving {
    pub length: f64,
    pub overlap: f32,
    pub half_width: f32,
    pub z: f32,
}

/// Paves `motion`'s whole path with slabs of `material` (structure: the path runs on them).
pub(super) fn pave(b: &mut SceneBuilder, motion: &Motion, paving: &Paving, material: Material) {
    let n = (motion.lap_length() / paving.length).ceil() as usize;
    let step = motion.lap_length() / n as f64;
    for k in 0..n {
        let f = PathFrame::at(motion, (k as f64 + 0.5) * step);
        let [x, y] = f.offset(0.0, 0.0);
        let half = [0.5 * step as f32 + paving.overlap, paving.half_width, 0.05];
        b.structure(Object::cuboid([x, y, paving.z], half, f.yaw(), material));
    }
}
