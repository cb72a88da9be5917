//! `lab`: a 14 m × 9 m × 3 m room with furniture; a ~1 m/s loop around its middle.

use rand::Rng;

use super::{indoor_light, Ambient, SceneBuilder};
use crate::motion::{Curve, Motion, Sway};
use crate::texture::{Material, Pattern};
use crate::world::Object;

/// Half extents of the room (x, y) and its height.
const HALF_X: f32 = 7.0;
const HALF_Y: f32 = 4.5;
const HEIGHT: f32 = 3.0;
/// Nominal walking speed, m/s.
const SPEED: f64 = 1.0;

/// Builds the lab room, its furniture and the loop trajectory.
pub(super) fn build(seed: u64, speed_scale: f64) -> (SceneBuilder, Motion, Ambient) {
    let mut b = SceneBuilder::new(seed, 1, 0.5);
    room(&mut b);
    for side in [-1.0f32, 1.0] {
        long_wall_furniture(&mut b, side);
        end_wall_furniture(&mut b, side);
    }
    centre(&mut b);
    let a = b.rng.random_range(3.6..4.0);
    let bb = b.rng.random_range(1.9..2.2);
    let sway = Sway {
        yaw_amp: 0.15,
        pitch_amp: 0.03,
        roll_amp: 0.025,
        bob_amp: 0.015,
        freq_hz: 0.6,
        phase: b.rng.random_range(0.0..std::f64::consts::TAU),
    };
    let curve = Curve::Ellipse {
        center: [0.0, 0.0],
        a,
        b: bb,
    };
    let motion = Motion::new(curve, SPEED * speed_scale, 1.2, sway);
    (b, motion, indoor_light())
}

/// Floor, ceiling and four walls (0.2 m thick, outside the free volume).
fn room(b: &mut SceneBuilder) {
    let (x, y, t) = (HALF_X, HALF_Y, 0.2);
    let floor = b.material(Pattern::Tiles { cell: 0.6 }, 0.3, 0.5);
    b.structure(Object::aabb_box(
        [-x - t, -y - t, -t],
        [x + t, y + t, 0.0],
        floor,
    ));
    let ceiling = b.material(Pattern::Tiles { cell: 1.2 }, 0.6, 0.8);
    let top = HEIGHT;
    b.structure(Object::aabb_box(
        [-x - t, -y - t, top],
        [x + t, y + t, top + t],
        ceiling,
    ));
    let walls = [
        ([-x - t, -y, 0.0], [-x, y, top]),
        ([x, -y, 0.0], [x + t, y, top]),
        ([-x - t, -y - t, 0.0], [x + t, -y, top]),
        ([-x - t, y, 0.0], [x + t, y + t, top]),
    ];
    for (lo, hi) in walls {
        let p = b.wall_pattern();
        let m = b.material(p, 0.4, 0.8);
        b.structure(Object::aabb_box(lo, hi, m));
    }
}

/// Shelves, tables and boxes along the wall at `y = side · HALF_Y`.
fn long_wall_furniture(b: &mut SceneBuilder, side: f32) {
    let mut x = -HALF_X + b.rng.random_range(0.2..0.8);
    while x < HALF_X - 0.8 {
        let width = b.rng.random_range(0.8..2.0f32).min(HALF_X - 0.1 - x);
        let cx = x + 0.5 * width;
        match b.rng.random_range(0..3) {
            0 => shelf(b, cx, side * (HALF_Y - 0.2), width, 0.4),
            1 => table(b, cx, side * (HALF_Y - 0.45), width, 0.8),
            _ => box_stack(b, cx, side * (HALF_Y - 0.4), width.min(0.9)),
        }
        x += width + b.rng.random_range(0.3..1.2);
    }
}

/// Furniture in the band between the loop and the wall at `x = side · HALF_X`.
fn end_wall_furniture(b: &mut SceneBuilder, side: f32) {
    let mut y = -HALF_Y + 1.2;
    while y < HALF_Y - 1.4 {
        let width = b.rng.random_range(0.8..1.6f32);
        let cy = y + 0.5 * width;
        match b.rng.random_range(0..3) {
            0 => shelf(b, side * (HALF_X - 0.2), cy, 0.4, width),
            1 => {
                let m = b.material(
                    Pattern::Posters {
                        cell_u: 0.5,
                        cell_v: 0.5,
                        density: 0.8,
                    },
                    0.2,
                    0.5,
                );
                let r = b.rng.random_range(0.18..0.3);
                let h = b.rng.random_range(0.6..1.1);
                b.prop(Object::cylinder([side * (HALF_X - 0.6), cy, 0.0], r, h, m));
            }
            _ => box_stack(b, side * (HALF_X - 0.6), cy, 0.8),
        }
        y += width + b.rng.random_range(0.3..0.9);
    }
}

/// A pillar, a column and a table inside the loop.
fn centre(b: &mut SceneBuilder) {
    let m = b.material(Pattern::Stripes { width: 0.1 }, 0.3, 0.7);
    let px = b.rng.random_range(0.8..1.6);
    b.structure(Object::aabb_box(
        [px - 0.2, -0.2, 0.0],
        [px + 0.2, 0.2, HEIGHT],
        m,
    ));
    let m = b.material(Pattern::Blobs { cell: 0.35 }, 0.4, 0.7);
    b.structure(Object::cylinder([-px, 0.0, 0.0], 0.25, HEIGHT, m));
    let ty = b.rng.random_range(-0.3..0.3);
    table(b, 0.0, ty, 1.0, 0.7);
    let m = b.material(Pattern::Tiles { cell: 0.12 }, 0.3, 0.7);
    b.prop(Object::cylinder([-2.3, 0.6, 0.0], 0.3, 0.9, m));
}

/// A box with footprint centre `c`, half extents `half` and vertical span `z`.
fn slab(c: [f32; 2], half: [f32; 2], z: (f32, f32), m: Material) -> Object {
    let lo = [c[0] - half[0], c[1] - half[1], z.0];
    Object::aabb_box(lo, [c[0] + half[0], c[1] + half[1], z.1], m)
}

/// A shelf unit centred at `(cx, cy)` with footprint `wx × wy`, sides on the short ends,
/// 2–4 boards and some items on them.
fn shelf(b: &mut SceneBuilder, cx: f32, cy: f32, wx: f32, wy: f32) {
    let h = b.rng.random_range(1.6..2.3f32);
    let p = b.prop_pattern();
    let m = b.material(p, 0.3, 0.8);
    let half = [0.5 * wx, 0.5 * wy];
    b.prop(slab([cx, cy], half, (0.0, 0.08), m));
    b.prop(slab([cx, cy], half, (h - 0.03, h), m));
    let side = if wx >= wy {
        [0.02, half[1]]
    } else {
        [half[0], 0.02]
    };
    for s in [-1.0, 1.0] {
        let c = if wx >= wy {
            [cx + s * (half[0] - 0.02), cy]
        } else {
            [cx, cy + s * (half[1] - 0.02)]
        };
        b.prop(slab(c, side, (0.0, h), m));
    }
    let boards = b.rng.random_range(2..5);
    let spacing = h / (boards + 1) as f32;
    for k in 1..=boards {
        let z = spacing * k as f32;
        b.prop(slab([cx, cy], half, (z - 0.015, z + 0.015), m));
        if b.rng.random_bool(0.6) {
            let p = b.prop_pattern();
            let item = b.material(p, 0.1, 0.9);
            let top = z + b.rng.random_range(0.12..(spacing - 0.02).max(0.13));
            let c = [cx - 0.14 * half[0], cy - 0.14 * half[1]];
            let ih = [0.56 * half[0], 0.56 * half[1]];
            b.prop(slab(c, ih, (z + 0.015, top), item));
        }
    }
}

/// A table of size `wx × wy` (0.72–0.78 m high) with four legs.
fn table(b: &mut SceneBuilder, cx: f32, cy: f32, wx: f32, wy: f32) {
    let h = b.rng.random_range(0.72..0.78f32);
    let p = b.prop_pattern();
    let m = b.material(p, 0.3, 0.8);
    let (hx, hy) = (0.5 * wx, 0.5 * wy);
    b.prop(Object::aabb_box(
        [cx - hx, cy - hy, h - 0.04],
        [cx + hx, cy + hy, h],
        m,
    ));
    for (sx, sy) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
        let (lx, ly) = (cx + sx * (hx - 0.05), cy + sy * (hy - 0.05));
        b.prop(Object::aabb_box(
            [lx - 0.025, ly - 0.025, 0.0],
            [lx + 0.025, ly + 0.025, h - 0.04],
            m,
        ));
    }
    if b.rng.random_bool(0.5) {
        let p = b.prop_pattern();
        let m = b.material(p, 0.1, 0.9);
        let s = b.rng.random_range(0.2..0.4f32);
        let yaw = b.rng.random_range(0.0..1.5);
        b.prop(Object::cuboid([cx, cy, h + 0.5 * s], [0.5 * s; 3], yaw, m));
    }
}

/// One to three boxes stacked at `(cx, cy)`, each smaller and slightly turned.
fn box_stack(b: &mut SceneBuilder, cx: f32, cy: f32, size: f32) {
    let mut z = 0.0;
    let mut s = size * b.rng.random_range(0.6..0.9f32);
    for _ in 0..b.rng.random_range(1..4) {
        let p = b.prop_pattern();
        let m = b.material(p, 0.15, 0.9);
        let h = s * b.rng.random_range(0.5..0.9f32);
        let yaw = b.rng.random_range(-0.3..0.3);
        b.prop(Object::cuboid(
            [cx, cy, z + 0.5 * h],
            [0.5 * s, 0.5 * s, 0.5 * h],
            yaw,
            m,
        ));
        z += h;
        s *= b.rng.random_range(0.6..0.95);
    }
}
