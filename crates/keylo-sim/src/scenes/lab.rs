//! `lab`: a 14 m × 9 m room with furniture, 3 m high (with the `ouster` appearance a
//! 16.5 m × 11 m hall, 4.5 m high, and its clutter: [`super::hall`]); a ~1 m/s loop around
//! its middle.

use rand::Rng;

use super::shapes::{slab, Room};
use super::{hall, indoor_light, Ambient, SceneBuilder};
use crate::motion::{Curve, Motion, Sway};
use crate::texture::Pattern;
use crate::world::Object;
use crate::Appearance;

/// The `ideal` lab.
const ROOM: Room = Room {
    half_x: 7.0,
    half_y: 4.5,
    height: 3.0,
};

/// The `ouster` lab is a hall. With the driver's square root, a 3 m ceiling fills the upper
/// rows with dim grazing ceiling, while the real images' upper rows are bright walls (mean
/// grey of the second eighth of the rows: real 151; 122 at 3 m, 158 at 4.5 m). It is
/// 16.5 m × 11 m: the real images' far walls meet the floor 10–12.5° below the horizon
/// (rows 77–80 of 128), which with the sensor 1.10–1.28 m up (the height of their doors,
/// docs/results/sim-realism.md) puts them 5–7 m away; in the 14 m × 9 m room the loop's
/// nearest walls are 2.5 m away and the corners along them crowd the rows 12–24° down.
const HALL: Room = Room {
    half_x: 8.25,
    half_y: 5.5,
    height: 4.5,
};

/// The room of an appearance.
fn room_of(look: Appearance) -> Room {
    match look {
        Appearance::Ideal => ROOM,
        Appearance::Ouster => HALL,
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
    let r = room_of(look);
    let mut b = SceneBuilder::new(seed, 1, 0.5);
    room(&mut b, r, look);
    for side in [-1.0f32, 1.0] {
        long_wall_furniture(&mut b, r, side);
        end_wall_furniture(&mut b, r, side);
    }
    // The hall's middle is open floor: the near items stand there (see `hall`).
    if look == Appearance::Ideal {
        centre(&mut b, r.height);
    }
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
        hall::clutter(&mut b, r, (a as f32, bb as f32));
    }
    (b, motion, indoor_light())
}

/// Floor tiles of the `ouster` lab: size and contrast.
const FLOOR_TILE_M: f32 = 0.6;
const FLOOR_TILE_CONTRAST: f32 = 0.3;
/// Share of the `ouster` floor's 0.1 m cells holding a bright fleck (see
/// [`Pattern::Flooring`]).
const FLOOR_FLECKS: f32 = 0.15;
/// The `ouster` floor's albedo: dark. With the driver's square root the real floor reads
/// grey 58–69 in the last two eighths of the rows; the still lab: 60 and 69.
const FLOOR_ALBEDO: (f32, f32) = (0.042, 0.07);

/// Floor, ceiling and four walls (0.2 m thick, outside the free volume).
fn room(b: &mut SceneBuilder, r: Room, look: Appearance) {
    let (x, y, t) = (r.half_x, r.half_y, 0.2);
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
    let top = r.height;
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

/// Shelves, tables and boxes along the wall at `y = side · half_y`.
fn long_wall_furniture(b: &mut SceneBuilder, r: Room, side: f32) {
    let mut x = -r.half_x + b.rng.random_range(0.2..0.8);
    while x < r.half_x - 0.8 {
        let width = b.rng.random_range(0.8..2.0f32).min(r.half_x - 0.1 - x);
        let cx = x + 0.5 * width;
        match b.rng.random_range(0..3) {
            0 => shelf(b, cx, side * (r.half_y - 0.2), width, 0.4),
            1 => table(b, cx, side * (r.half_y - 0.45), width, 0.8),
            _ => box_stack(b, cx, side * (r.half_y - 0.4), width.min(0.9)),
        }
        x += width + b.rng.random_range(0.3..1.2);
    }
}

/// Furniture in the band between the loop and the wall at `x = side · half_x`.
fn end_wall_furniture(b: &mut SceneBuilder, r: Room, side: f32) {
    let mut y = -r.half_y + 1.2;
    while y < r.half_y - 1.4 {
        let width = b.rng.random_range(0.8..1.6f32);
        let cy = y + 0.5 * width;
        match b.rng.random_range(0..3) {
            0 => shelf(b, side * (r.half_x - 0.2), cy, 0.4, width),
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
                let radius = b.rng.random_range(0.18..0.3);
                let h = b.rng.random_range(0.6..1.1);
                let base = [side * (r.half_x - 0.6), cy, 0.0];
                b.prop(Object::cylinder(base, radius, h, m));
            }
            _ => box_stack(b, side * (r.half_x - 0.6), cy, 0.8),
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
