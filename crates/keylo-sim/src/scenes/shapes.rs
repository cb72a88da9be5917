//! Shapes shared by the indoor scenes (the lab and its hall clutter).

use crate::texture::Material;
use crate::world::Object;

/// A room's half extents (x, y) and its height, metres.
#[derive(Debug, Clone, Copy)]
pub(super) struct Room {
    pub half_x: f32,
    pub half_y: f32,
    pub height: f32,
}

/// A box with footprint centre `c`, half extents `half` and vertical span `z`.
pub(super) fn slab(c: [f32; 2], half: [f32; 2], z: (f32, f32), m: Material) -> Object {
    let lo = [c[0] - half[0], c[1] - half[1], z.0];
    Object::aabb_box(lo, [c[0] + half[0], c[1] + half[1], z.1], m)
}
