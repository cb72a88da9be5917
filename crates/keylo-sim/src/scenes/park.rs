//! `park`: an unstructured outdoor scene. A gravel path loops ~270 m through a wooded park
//! over rolling grass: trees of every size (trunks, irregular crowns of several lobes), bushes,
//! rocks and low mounds, with a few benches, bins and lamp posts; the sensor is carried along
//! the path at ~1.4 m/s. Vegetation is bright at the sensor's 865 nm (leaves and grass reflect
//! 40–60 % there), bark and soil darker.

use std::ops::Range;

use rand::Rng;

use super::path_frame::{pave, PathFrame, Paving};
use super::{Ambient, SceneBuilder};
use crate::motion::{Curve, Motion, Sway};
use crate::texture::{Material, Pattern};
use crate::world::Object;
use parry3d::math::Vector as GVec;

/// Nominal walking speed, m/s.
const SPEED: f64 = 1.4;
/// Length of one path slab, metres.
const SLAB: f64 = 3.0;
/// Half width of the gravel path.
const PATH_HALF_WIDTH: f32 = 1.2;
/// Trees grow this far from the path's centre line, metres.
const WOOD_DEPTH: f64 = 35.0;
/// Trees per 100 m² of wood.
const TREES_PER_100_M2: f64 = 1.2;

/// Builds the park loop and its surroundings.
pub(super) fn build(seed: u64, speed_scale: f64) -> (SceneBuilder, Motion, Ambient) {
    let mut b = SceneBuilder::new(seed, 4, 0.6);
    let curve = Curve::Loop {
        a: b.rng.random_range(45.0..55.0),
        b: b.rng.random_range(25.0..32.0),
        wobble: b.rng.random_range(6.0..10.0),
    };
    let sway = Sway {
        yaw_amp: 0.08,
        pitch_amp: 0.03,
        roll_amp: 0.025,
        bob_amp: 0.02,
        freq_hz: 0.9,
        phase: b.rng.random_range(0.0..std::f64::consts::TAU),
    };
    let motion = Motion::new(curve, SPEED * speed_scale, 1.2, sway);
    ground(&mut b, &motion);
    mounds(&mut b, &motion);
    woods(&mut b, &motion);
    furniture(&mut b, &motion);
    let ambient = Ambient {
        light_dir: GVec::new(0.3, -0.2, 0.9).normalize(),
        direct: 1100.0,
        diffuse: 450.0,
        sky: 300.0,
    };
    (b, motion, ambient)
}

/// A mottled material (grass, leaves, gravel, stone): mottles of `cell` metres, albedo
/// `± contrast` around a base drawn in `albedo`.
fn mottled(b: &mut SceneBuilder, cell: f32, contrast: f32, albedo: Range<f32>) -> Material {
    b.material(
        Pattern::Mottled { cell, contrast },
        albedo.start,
        albedo.end,
    )
}

/// Grass everywhere, and the gravel path's slabs along the centre line.
fn ground(b: &mut SceneBuilder, motion: &Motion) {
    let grass = mottled(b, 0.35, 0.35, 0.35..0.5);
    b.structure(Object::aabb_box(
        [-110.0, -90.0, -1.0],
        [110.0, 90.0, 0.0],
        grass,
    ));
    let gravel = mottled(b, 0.08, 0.3, 0.25..0.35);
    let paving = Paving {
        length: SLAB,
        overlap: 0.2,
        half_width: PATH_HALF_WIDTH,
        z: -0.03,
    };
    pave(b, motion, &paving, gravel);
}

/// Low grassy mounds (caps of large buried balls) beside the path, clear of it.
fn mounds(b: &mut SceneBuilder, motion: &Motion) {
    let lap = motion.lap_length();
    let mut s = b.rng.random_range(0.0..15.0);
    while s < lap {
        let radius = b.rng.random_range(4.0..12.0f32);
        let height = b.rng.random_range(0.3..1.2f32);
        let foot = (radius * radius - (radius - height).powi(2)).sqrt();
        let side = b.random_side();
        let lateral = f64::from(PATH_HALF_WIDTH + foot) + b.rng.random_range(1.0..12.0);
        let [x, y] = PathFrame::at(motion, s).offset(0.0, side * lateral);
        let turf = mottled(b, 0.3, 0.35, 0.3..0.5);
        b.prop(Object::ball([x, y, height - radius], radius, turf));
        s += b.rng.random_range(12.0..30.0);
    }
}

/// Trees, bushes and rocks on both sides, spread evenly up to `WOOD_DEPTH` from the path.
fn woods(b: &mut SceneBuilder, motion: &Motion) {
    let lap = motion.lap_length();
    let trees = (TREES_PER_100_M2 * lap * 2.0 * WOOD_DEPTH / 100.0) as usize;
    for _ in 0..trees {
        let [x, y] = beside_path(b, motion, 2.5);
        tree(b, x, y);
    }
    for _ in 0..trees {
        let [x, y] = beside_path(b, motion, 1.8);
        if b.rng.random_bool(0.7) {
            bush(b, x, y);
        } else {
            rock(b, x, y);
        }
    }
}

/// A random place on either side of the path, `nearest` to `WOOD_DEPTH` metres from its
/// centre line.
fn beside_path(b: &mut SceneBuilder, motion: &Motion, nearest: f64) -> [f32; 2] {
    let s = b.rng.random_range(0.0..motion.lap_length());
    let side = b.random_side();
    let lateral = b.rng.random_range(nearest..WOOD_DEPTH);
    PathFrame::at(motion, s).offset(0.0, side * lateral)
}

/// A trunk and a crown of several overlapping lobes (a dead snag has none).
fn tree(b: &mut SceneBuilder, x: f32, y: f32) {
    let width = b.rng.random_range(0.03..0.08);
    let bark = b.material(Pattern::Stripes { width }, 0.15, 0.35);
    let trunk_r = b.rng.random_range(0.06..0.4f32);
    let trunk_h = b.rng.random_range(1.5..3.0f32) + 8.0 * trunk_r;
    b.prop(Object::cylinder([x, y, 0.0], trunk_r, trunk_h, bark));
    if b.rng.random_bool(0.08) {
        return;
    }
    let cell = b.rng.random_range(0.15..0.4);
    let leaves = mottled(b, cell, 0.5, 0.35..0.6);
    let spread = 1.0 + 6.0 * trunk_r;
    for _ in 0..b.rng.random_range(3..7) {
        let r = spread * b.rng.random_range(0.35..0.7f32);
        let dx = spread * b.rng.random_range(-0.6..0.6f32);
        let dy = spread * b.rng.random_range(-0.6..0.6f32);
        let dz = spread * b.rng.random_range(-0.3..0.5f32);
        b.prop(Object::ball([x + dx, y + dy, trunk_h + dz], r, leaves));
    }
}

/// A bush: two to four leafy lobes on the ground.
fn bush(b: &mut SceneBuilder, x: f32, y: f32) {
    let leaves = mottled(b, 0.15, 0.5, 0.3..0.55);
    for _ in 0..b.rng.random_range(2..5) {
        let r = b.rng.random_range(0.25..0.8f32);
        let dx = b.rng.random_range(-0.6..0.6f32);
        let dy = b.rng.random_range(-0.6..0.6f32);
        b.prop(Object::ball([x + dx, y + dy, 0.6 * r], r, leaves));
    }
}

/// A rock, half buried, turned at random.
fn rock(b: &mut SceneBuilder, x: f32, y: f32) {
    let stone = mottled(b, 0.1, 0.3, 0.15..0.4);
    let half = [
        b.rng.random_range(0.15..0.6f32),
        b.rng.random_range(0.15..0.5f32),
        b.rng.random_range(0.1..0.35f32),
    ];
    let yaw = b.rng.random_range(0.0..std::f32::consts::TAU);
    b.prop(Object::cuboid([x, y, 0.5 * half[2]], half, yaw, stone));
}

/// Benches, bins and lamp posts along the path's edges.
fn furniture(b: &mut SceneBuilder, motion: &Motion) {
    let lap = motion.lap_length();
    let mut s = b.rng.random_range(0.0..20.0);
    while s < lap - 5.0 {
        let f = PathFrame::at(motion, s);
        let side = b.random_side();
        let edge = f64::from(PATH_HALF_WIDTH) + 0.6;
        match b.rng.random_range(0..3) {
            0 => {
                let wood = b.material(Pattern::Stripes { width: 0.1 }, 0.3, 0.55);
                let [x, y] = f.offset(0.0, side * edge);
                b.prop(Object::cuboid(
                    [x, y, 0.45],
                    [0.9, 0.22, 0.04],
                    f.yaw(),
                    wood,
                ));
                let [bx, by] = f.offset(0.0, side * (edge + 0.22));
                b.prop(Object::cuboid(
                    [bx, by, 0.75],
                    [0.9, 0.03, 0.2],
                    f.yaw(),
                    wood,
                ));
            }
            1 => {
                let metal = b.material(Pattern::Plain, 0.1, 0.3);
                let [x, y] = f.offset(0.0, side * edge);
                b.prop(Object::cylinder([x, y, 0.0], 0.25, 0.9, metal));
            }
            _ => {
                let metal = b.material(Pattern::Plain, 0.2, 0.4);
                let [x, y] = f.offset(0.0, side * (edge + 0.3));
                b.prop(Object::cylinder([x, y, 0.0], 0.07, 4.0, metal));
            }
        }
        s += b.rng.random_range(12.0..35.0);
    }
}
