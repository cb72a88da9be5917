//! A local frame along a scene's path (its centre line), for placing things beside it.

use nalgebra::Vector2;

use crate::motion::Motion;

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
