//! `lab`: a 14 m × 9 m room with furniture, 3 m high (4.5 m with the `ouster` appearance);
//! a ~1 m/s loop around its middle.

use rand::Rng;

use super::{indoor_light, Ambient, SceneBuilder};
use crate::motion::{Curve, Motion, Sway};
use crate::texture::{Material, Pattern};
use crate::world::Object;
use crate::Appearance;

/// Half extents of the room (x, y) and its height.
const HALF_X: f32 = 7.0;
const HALF_Y: f32 = 4.5;
const HEIGHT: f32 = 3.0;
/// The `ouster` lab is a hall: with the driver's square root, a 3 m ceiling fills the upper
/// rows with dim grazing ceiling, while the real images' upper rows are bright walls (mean
/// grey of the second eighth of the rows: real 151; 122 at 3 m, 158 at 4.5 m).
const HALL_HEIGHT: f32 = 4.5;

/// The room's height.
fn height(look: Appearance) -> f32 {
    match look {
        Appearance::Ideal => HEIGHT,
        Appearance::Ouster => HALL_HEIGHT,
    }
}

/// Nominal walking speed, m/s.
const SPEED: f64 = 1.0;

/// Builds the lab room, its furniture and the loop trajectory.
pub(super) fn build(
    seed: u64,
    speed_scale: f64,
    look: Appearance,
) -> (SceneBuilder, Motion, Ambient) {
    let mut b = SceneBuilder::new(seed, 1, 0.5);
    room(&mut b, look);
    for side in [-1.0f32, 1.0] {
        long_wall_furniture(&mut b, side);
        end_wall_furniture(&mut b, side);
    }
    centre(&mut b, height(look));
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
    if look == Appearance::Ouster {
        clutter(&mut b);
    }
    (b, motion, indoor_light())
}

/// Floor tiles of the `ouster` lab: size and contrast.
const FLOOR_TILE_M: f32 = 0.6;
const FLOOR_TILE_CONTRAST: f32 = 0.3;
/// Share of the `ouster` floor's 0.1 m cells holding a bright fleck (see
/// [`Pattern::Flooring`]).
const FLOOR_FLECKS: f32 = 0.3;
/// The `ouster` floor's albedo: dark. With the driver's square root the real floor reads
/// grey 58–69 in the last two eighths of the rows; the still lab: 60 and 69.
const FLOOR_ALBEDO: (f32, f32) = (0.042, 0.07);

/// Floor, ceiling and four walls (0.2 m thick, outside the free volume).
fn room(b: &mut SceneBuilder, look: Appearance) {
    let (x, y, t) = (HALF_X, HALF_Y, 0.2);
    // A real hall's floor is one material, not a checkerboard (same random draws).
    let (floor_pattern, lo, hi) = match look {
        Appearance::Ideal => (Pattern::Tiles { cell: 0.6 }, 0.3, 0.5),
        Appearance::Ouster => (
            Pattern::Flooring {
                cell: FLOOR_TILE_M,
                contrast: FLOOR_TILE_CONTRAST,
                flecks: FLOOR_FLECKS,
            },
            FLOOR_ALBEDO.0,
            FLOOR_ALBEDO.1,
        ),
    };
    let floor = b.material(floor_pattern, lo, hi);
    b.structure(Object::aabb_box(
        [-x - t, -y - t, -t],
        [x + t, y + t, 0.0],
        floor,
    ));
    let (ceiling_pattern, lo, hi) = match look {
        Appearance::Ideal => (Pattern::Tiles { cell: 1.2 }, 0.6, 0.8),
        Appearance::Ouster => (Pattern::Plain, 0.25, 0.35),
    };
    let ceiling = b.material(ceiling_pattern, lo, hi);
    let top = height(look);
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
        // Painted walls (the pattern is still drawn, so the layout keeps its random draws).
        let p = match look {
            Appearance::Ideal => p,
            Appearance::Ouster => Pattern::Plain,
        };
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
fn centre(b: &mut SceneBuilder, top: f32) {
    let m = b.material(Pattern::Stripes { width: 0.1 }, 0.3, 0.7);
    let px = b.rng.random_range(0.8..1.6);
    b.structure(Object::aabb_box(
        [px - 0.2, -0.2, 0.0],
        [px + 0.2, 0.2, top],
        m,
    ));
    let m = b.material(Pattern::Blobs { cell: 0.35 }, 0.4, 0.7);
    b.structure(Object::cylinder([-px, 0.0, 0.0], 0.25, top, m));
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

/// What a real hall holds besides the big furniture (the `ouster` appearance): ceiling lights,
/// ducts and cable trays, doors, tall cabinets, chairs and small things on the floor along
/// the walls — the small, high-contrast shapes that give real signal images most of their
/// corners.
fn clutter(b: &mut SceneBuilder) {
    ceiling_lights(b);
    for _ in 0..DARK_ITEMS {
        let at = wall_band(b);
        let m = b.material(Pattern::Plain, 0.02, 0.05);
        standing_box(b, at, m, [0.5..1.4, 0.4..0.8, 0.4..1.2]);
    }
    for _ in 0..WALL_ITEMS {
        wall_item(b);
    }
    for _ in 0..CABINETS {
        cabinet(b);
    }
    for _ in 0..CEILING_RUNS {
        ceiling_run(b);
    }
    for side in [-1.0f32, 1.0] {
        door(b, side);
    }
    for _ in 0..CHAIRS {
        let (cx, cy) = wall_band(b);
        chair(b, cx, cy);
    }
    for _ in 0..FLOOR_ITEMS {
        let (cx, cy) = wall_band(b);
        let m = b.material(Pattern::Plain, 0.15, 0.6);
        let s = b.rng.random_range(0.12..0.45f32);
        let h = s * b.rng.random_range(0.4..1.2f32);
        let yaw = b.rng.random_range(0.0..1.5);
        b.prop(Object::cuboid(
            [cx, cy, 0.5 * h],
            [0.5 * s, 0.5 * s, 0.5 * h],
            yaw,
            m,
        ));
    }
    for _ in 0..POLES {
        let (cx, cy) = wall_band(b);
        let m = b.material(Pattern::Plain, 0.1, 0.8);
        let h = b.rng.random_range(1.0..1.9f32);
        b.prop(Object::cylinder([cx, cy, 0.0], 0.02, h, m));
    }
}

/// Clutter counts of the `ouster` lab. Chosen, with the floor's flecks and how high wall
/// items go, by a random search of 45 settings and a local search from the best, each
/// setting measured on still layouts (the keypoint counts of `keylo sim realism`'s seven
/// detectors), for the most counts inside the real images' interquartile ranges; checked on
/// other layouts (docs/results/sim-realism.md).
const CHAIRS: usize = 64;
const FLOOR_ITEMS: usize = 70;
const POLES: usize = 48;
const WALL_ITEMS: usize = 100;
/// Tall cabinets and racks.
const CABINETS: usize = 5;
/// Ducts and cable trays under the ceiling.
const CEILING_RUNS: usize = 4;
/// Black furniture and equipment: weak, broken returns.
const DARK_ITEMS: usize = 4;

/// Highest a wall item starts, metres.
const WALL_ITEMS_TOP_M: f32 = 4.2;

/// A tall cabinet or rack (1.8–2.6 m) with labels or panels, in the band along the walls.
fn cabinet(b: &mut SceneBuilder) {
    let at = wall_band(b);
    let p = b.prop_pattern();
    let m = b.material(p, 0.2, 0.8);
    standing_box(b, at, m, [0.5..1.2, 0.4..0.7, 1.8..2.6]);
}

/// A box standing on the floor at `(cx, cy)`, its width, depth and height drawn from
/// `sizes`, turned by up to 0.3 rad.
fn standing_box(
    b: &mut SceneBuilder,
    (cx, cy): (f32, f32),
    m: Material,
    sizes: [std::ops::Range<f32>; 3],
) {
    let [w, d, h] = sizes.map(|r| b.rng.random_range(r));
    let yaw = b.rng.random_range(-0.3..0.3);
    b.prop(Object::cuboid(
        [cx, cy, 0.5 * h],
        [0.5 * w, 0.5 * d, 0.5 * h],
        yaw,
        m,
    ));
}

/// A duct or cable tray the length (or width) of the hall, 0.08–0.4 m thick, hanging
/// 0.05–0.9 m below the ceiling.
fn ceiling_run(b: &mut SceneBuilder) {
    let m = b.material(Pattern::Plain, 0.3, 0.9);
    let along_x = b.rng.random_bool(0.5);
    let thick = b.rng.random_range(0.08..0.4f32);
    let top = HALL_HEIGHT - b.rng.random_range(0.05..0.9f32);
    let (lo, hi) = if along_x {
        let y = b.rng.random_range(-HALF_Y..HALF_Y - thick);
        ([-HALF_X, y, top - thick], [HALF_X, y + thick, top])
    } else {
        let x = b.rng.random_range(-HALF_X..HALF_X - thick);
        ([x, -HALF_Y, top - thick], [x + thick, HALF_Y, top])
    };
    b.structure(Object::aabb_box(lo, hi, m));
}

/// A sign, switch box or notice on one of the four walls, 0.8–4.2 m up.
fn wall_item(b: &mut SceneBuilder) {
    let m = b.material(Pattern::Plain, 0.2, 0.7);
    let (w, h) = (
        b.rng.random_range(0.1..0.6f32),
        b.rng.random_range(0.1..0.5f32),
    );
    let z = b.rng.random_range(0.8..WALL_ITEMS_TOP_M);
    let depth = 0.03;
    // 60 % on the long walls (along x), the rest on the end walls (along y).
    let long_wall = b.rng.random_bool(0.6);
    let (half_along, half_across) = if long_wall {
        (HALF_X, HALF_Y)
    } else {
        (HALF_Y, HALF_X)
    };
    let along = b.rng.random_range(-half_along + 0.5..half_along - 0.5);
    let across = if b.rng.random_bool(0.5) {
        half_across - depth
    } else {
        -half_across
    };
    let (lo, hi) = if long_wall {
        ([along, across, z], [along + w, across + depth, z + h])
    } else {
        ([across, along, z], [across + depth, along + w, z + h])
    };
    b.structure(Object::aabb_box(lo, hi, m));
}

/// A point in the band between the loop and the walls.
fn wall_band(b: &mut SceneBuilder) -> (f32, f32) {
    if b.rng.random_bool(0.7) {
        let x = b.rng.random_range(-HALF_X + 0.5..HALF_X - 0.5);
        let y = b.rng.random_range(HALF_Y - 1.3..HALF_Y - 0.6);
        (x, if b.rng.random_bool(0.5) { y } else { -y })
    } else {
        let y = b.rng.random_range(-HALF_Y + 0.6..HALF_Y - 0.6);
        let x = b.rng.random_range(HALF_X - 1.6..HALF_X - 0.9);
        (if b.rng.random_bool(0.5) { x } else { -x }, y)
    }
}

/// Bright light panels just below the ceiling on a 2.4 m grid.
fn ceiling_lights(b: &mut SceneBuilder) {
    let m = b.material(Pattern::Plain, 0.85, 0.95);
    let mut x = -HALF_X + 1.2;
    while x < HALF_X - 0.6 {
        let mut y = -HALF_Y + 1.0;
        while y < HALF_Y - 0.5 {
            b.structure(Object::aabb_box(
                [x - 0.3, y - 0.6, HALL_HEIGHT - 0.04],
                [x + 0.3, y + 0.6, HALL_HEIGHT],
                m,
            ));
            y += 2.4;
        }
        x += 2.4;
    }
}

/// A dark door (and its lighter frame) in the wall at `x = side · HALF_X`.
fn door(b: &mut SceneBuilder, side: f32) {
    let y = b.rng.random_range(-HALF_Y + 1.0..HALF_Y - 2.0);
    let frame = b.material(Pattern::Plain, 0.6, 0.8);
    let leaf = b.material(Pattern::Plain, 0.05, 0.15);
    let x = side * HALF_X;
    let inward = -side * 0.04;
    let (lo, hi) = (x.min(x + inward), x.max(x + inward));
    b.structure(Object::aabb_box(
        [lo, y - 0.1, 0.0],
        [hi, y + 1.1, 2.2],
        frame,
    ));
    let (lo, hi) = (x.min(x + 1.5 * inward), x.max(x + 1.5 * inward));
    b.structure(Object::aabb_box([lo, y, 0.0], [hi, y + 1.0, 2.1], leaf));
}

/// A chair at `(cx, cy)`: four legs, a seat and a back, turned at random.
fn chair(b: &mut SceneBuilder, cx: f32, cy: f32) {
    let m = b.material(Pattern::Plain, 0.15, 0.5);
    let yaw = b.rng.random_range(0.0..std::f32::consts::TAU);
    let (s, c) = yaw.sin_cos();
    let at = |dx: f32, dy: f32| [cx + c * dx - s * dy, cy + s * dx + c * dy];
    for (dx, dy) in [(-0.2, -0.2), (-0.2, 0.2), (0.2, -0.2), (0.2, 0.2)] {
        let [x, y] = at(dx, dy);
        b.prop(Object::cylinder([x, y, 0.0], 0.015, 0.45, m));
    }
    b.prop(Object::cuboid([cx, cy, 0.46], [0.23, 0.23, 0.02], yaw, m));
    let [x, y] = at(-0.21, 0.0);
    b.prop(Object::cuboid([x, y, 0.7], [0.02, 0.22, 0.22], yaw, m));
}
