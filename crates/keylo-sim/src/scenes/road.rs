//! `road`: a closed ~750 m loop road with building blocks (with gaps) on both sides, poles,
//! trees and parked cars; the sensor drives along the centre line at ~8 m/s.

use rand::Rng;

use super::path_frame::{pave, PathFrame, Paving};
use super::{Ambient, SceneBuilder};
use crate::motion::{Curve, Motion, Sway};
use crate::texture::Pattern;
use crate::world::Object;
use parry3d::math::Vector as GVec;

/// Nominal driving speed, m/s.
const SPEED: f64 = 8.0;
/// Length of one road slab, metres.
const SLAB: f64 = 8.0;
/// Half width of the paved road.
const ROAD_HALF_WIDTH: f32 = 7.0;

/// Builds the road loop and its surroundings.
pub(super) fn build(seed: u64, speed_scale: f64) -> (SceneBuilder, Motion, Ambient) {
    let mut b = SceneBuilder::new(seed, 3, 1.0);
    let curve = Curve::Loop {
        a: b.rng.random_range(140.0..160.0),
        b: b.rng.random_range(75.0..85.0),
        wobble: b.rng.random_range(8.0..14.0),
    };
    let sway = Sway {
        yaw_amp: 0.01,
        pitch_amp: 0.008,
        roll_amp: 0.006,
        bob_amp: 0.01,
        freq_hz: 1.1,
        phase: b.rng.random_range(0.0..std::f64::consts::TAU),
    };
    let motion = Motion::new(curve, SPEED * speed_scale, 1.8, sway);
    ground(&mut b, &motion);
    for side in [-1.0, 1.0] {
        buildings(&mut b, &motion, side);
        poles_and_trees(&mut b, &motion, side);
    }
    parked_cars(&mut b, &motion);
    let ambient = Ambient {
        light_dir: GVec::new(0.35, 0.25, 0.9).normalize(),
        direct: 1500.0,
        diffuse: 400.0,
        sky: 350.0,
    };
    (b, motion, ambient)
}

/// The ground plane (paving) and the road slabs along the centre line.
fn ground(b: &mut SceneBuilder, motion: &Motion) {
    let paving = b.material(Pattern::Tiles { cell: 1.0 }, 0.2, 0.35);
    b.structure(Object::aabb_box(
        [-260.0, -160.0, -1.0],
        [260.0, 160.0, 0.0],
        paving,
    ));
    let asphalt = b.material(Pattern::Road, 0.1, 0.14);
    let paving = Paving {
        length: SLAB,
        overlap: 0.3,
        half_width: ROAD_HALF_WIDTH,
        z: -0.04,
    };
    pave(b, motion, &paving, asphalt);
}

/// Building blocks 13 m or more from the centre line, with gaps between them.
fn buildings(b: &mut SceneBuilder, motion: &Motion, side: f64) {
    let lap = motion.lap_length();
    let mut s = b.rng.random_range(0.0..10.0);
    while s < lap - 20.0 {
        let len = b.rng.random_range(12.0..35.0);
        let depth = b.rng.random_range(8.0..20.0);
        let height = b.rng.random_range(6.0..25.0f32);
        let f = PathFrame::at(motion, s + 0.5 * len);
        let [x, y] = f.offset(0.0, side * (13.0 + 0.5 * depth));
        let pattern = if b.rng.random_bool(0.7) {
            Pattern::Windows {
                cell_u: b.rng.random_range(2.5..4.0),
                cell_v: b.rng.random_range(2.8..3.6),
            }
        } else {
            b.wall_pattern()
        };
        let m = b.material(pattern, 0.3, 0.75);
        let half = [0.5 * len as f32, 0.5 * depth as f32, 0.5 * height];
        b.prop(Object::cuboid([x, y, 0.5 * height], half, f.yaw(), m));
        s += len + b.rng.random_range(4.0..15.0);
    }
}

/// Street-light poles with a sign, and trees (trunk + crown) along the pavement.
fn poles_and_trees(b: &mut SceneBuilder, motion: &Motion, side: f64) {
    let lap = motion.lap_length();
    let mut s = b.rng.random_range(0.0..10.0);
    while s < lap - 5.0 {
        let f = PathFrame::at(motion, s);
        if b.rng.random_bool(0.4) {
            let [x, y] = f.offset(0.0, side * 8.0);
            let m = b.material(Pattern::Stripes { width: 0.05 }, 0.3, 0.6);
            let h = b.rng.random_range(5.0..7.0f32);
            b.prop(Object::cylinder([x, y, 0.0], 0.1, h, m));
            let sign = b.material(
                Pattern::Posters {
                    cell_u: 0.6,
                    cell_v: 0.6,
                    density: 1.0,
                },
                0.7,
                0.9,
            );
            let z = b.rng.random_range(2.2..3.0f32);
            let [sx, sy] = f.offset(0.0, side * 7.7);
            b.prop(Object::cuboid([sx, sy, z], [0.3, 0.02, 0.3], f.yaw(), sign));
        } else {
            let [x, y] = f.offset(0.0, side * b.rng.random_range(9.5..11.0));
            let bark = b.material(Pattern::Stripes { width: 0.06 }, 0.15, 0.35);
            let trunk_r = b.rng.random_range(0.15..0.25f32);
            let trunk_h = b.rng.random_range(2.0..3.2f32);
            b.prop(Object::cylinder([x, y, 0.0], trunk_r, trunk_h, bark));
            let leaves = b.material(Pattern::Blobs { cell: 0.5 }, 0.3, 0.5);
            let r = b.rng.random_range(1.2..2.2f32);
            b.prop(Object::ball([x, y, trunk_h + 0.8 * r], r, leaves));
        }
        s += b.rng.random_range(10.0..25.0);
    }
}

/// Groups of parked cars (body + cabin) along both kerbs.
fn parked_cars(b: &mut SceneBuilder, motion: &Motion) {
    let lap = motion.lap_length();
    let mut s = b.rng.random_range(5.0..30.0);
    while s < lap - 10.0 {
        let side = b.random_side();
        for _ in 0..b.rng.random_range(1..5) {
            let f = PathFrame::at(motion, s);
            let [x, y] = f.offset(0.0, side * 5.2);
            let p = b.prop_pattern();
            let paint = b.material(p, 0.1, 0.9);
            let yaw = f.yaw() + b.rng.random_range(-0.05..0.05);
            b.prop(Object::cuboid([x, y, 0.65], [2.2, 0.9, 0.45], yaw, paint));
            let glass = b.material(Pattern::Blobs { cell: 0.4 }, 0.05, 0.2);
            let [cx, cy] = f.offset(-0.3, side * 5.2);
            b.prop(Object::cuboid([cx, cy, 1.35], [1.1, 0.8, 0.25], yaw, glass));
            s += b.rng.random_range(5.0..6.5);
        }
        s += b.rng.random_range(20.0..60.0);
    }
}
