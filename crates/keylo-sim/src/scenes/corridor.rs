//! `corridor`: an 80 m × 2.4 m × 3 m hall, degenerate along x: door recesses, a few shallow
//! boxes, ceiling lights, and posters on the walls. The sensor walks along it at ~1.2 m/s
//! (and back, on a stadium-shaped lap).

use rand::Rng;

use super::{indoor_light, Ambient, SceneBuilder};
use crate::motion::{Curve, Motion, Sway};
use crate::texture::Pattern;
use crate::world::Object;

/// Length of the hall, metres (x from 0).
const LENGTH: f32 = 80.0;
/// Half width of the hall (inner wall faces at `y = ±HALF_WIDTH`).
const HALF_WIDTH: f32 = 1.2;
/// Depth of the door recesses.
const RECESS: f32 = 0.15;
const HEIGHT: f32 = 3.0;
const DOOR_HEIGHT: f32 = 2.1;
/// Nominal walking speed, m/s.
const SPEED: f64 = 1.2;

/// Builds the corridor and its stadium-shaped walking lap.
pub(super) fn build(seed: u64, speed_scale: f64) -> (SceneBuilder, Motion, Ambient) {
    let mut b = SceneBuilder::new(seed, 2, 0.35);
    shell(&mut b);
    for side in [-1.0f32, 1.0] {
        let poster = Pattern::Posters {
            cell_u: b.rng.random_range(1.4..2.2),
            cell_v: b.rng.random_range(1.0..1.5),
            density: b.rng.random_range(0.5..0.8),
        };
        let wall = b.material(poster, 0.55, 0.8);
        side_wall(&mut b, side, wall);
        wall_boxes(&mut b, side);
    }
    lights(&mut b);
    let sway = Sway {
        yaw_amp: 0.06,
        pitch_amp: 0.03,
        roll_amp: 0.02,
        bob_amp: 0.02,
        freq_hz: 0.9,
        phase: b.rng.random_range(0.0..std::f64::consts::TAU),
    };
    let curve = Curve::Stadium {
        x0: 4.0,
        x1: f64::from(LENGTH) - 4.0,
        half_width: 0.55,
    };
    let motion = Motion::new(curve, SPEED * speed_scale, 1.5, sway);
    (b, motion, indoor_light())
}

/// Floor, ceiling, end walls and the walls behind the door recesses.
fn shell(b: &mut SceneBuilder) {
    let (w, t) = (HALF_WIDTH + RECESS + 0.2, 0.2);
    let floor = b.material(Pattern::Tiles { cell: 0.5 }, 0.25, 0.45);
    b.structure(Object::aabb_box([-t, -w, -t], [LENGTH + t, w, 0.0], floor));
    let ceiling = b.material(Pattern::Tiles { cell: 1.2 }, 0.6, 0.8);
    b.structure(Object::aabb_box(
        [-t, -w, HEIGHT],
        [LENGTH + t, w, HEIGHT + t],
        ceiling,
    ));
    for x in [-t, LENGTH] {
        let m = b.material(Pattern::Blobs { cell: 0.8 }, 0.4, 0.7);
        b.structure(Object::aabb_box([x, -w, 0.0], [x + t, w, HEIGHT], m));
    }
    let back = b.material(Pattern::Stripes { width: 0.25 }, 0.3, 0.6);
    let inner = HALF_WIDTH + RECESS;
    b.structure(Object::aabb_box(
        [0.0, inner, 0.0],
        [LENGTH, inner + t, HEIGHT],
        back,
    ));
    b.structure(Object::aabb_box(
        [0.0, -inner - t, 0.0],
        [LENGTH, -inner, HEIGHT],
        back,
    ));
}

/// The wall at `y = side · HALF_WIDTH`, in segments between doors, with lintels over them.
fn side_wall(b: &mut SceneBuilder, side: f32, wall: crate::texture::Material) {
    let (y0, y1) = sorted(side * HALF_WIDTH, side * (HALF_WIDTH + RECESS));
    let mut x = 0.0;
    loop {
        let door_x = x + b.rng.random_range(5.0..12.0f32);
        let door_w = b.rng.random_range(0.9..1.1f32);
        if door_x + door_w > LENGTH - 1.0 {
            b.structure(Object::aabb_box([x, y0, 0.0], [LENGTH, y1, HEIGHT], wall));
            return;
        }
        b.structure(Object::aabb_box([x, y0, 0.0], [door_x, y1, HEIGHT], wall));
        let lintel = [door_x, y0, DOOR_HEIGHT];
        b.structure(Object::aabb_box(
            lintel,
            [door_x + door_w, y1, HEIGHT],
            wall,
        ));
        let p = b.prop_pattern();
        let door = b.material(p, 0.2, 0.7);
        let (d0, d1) = sorted(
            side * (HALF_WIDTH + RECESS - 0.03),
            side * (HALF_WIDTH + RECESS),
        );
        b.structure(Object::aabb_box(
            [door_x, d0, 0.0],
            [door_x + door_w, d1, DOOR_HEIGHT],
            door,
        ));
        x = door_x + door_w;
    }
}

/// A few shallow boxes on the wall (radiators, cabinets), at most 0.12 m deep.
fn wall_boxes(b: &mut SceneBuilder, side: f32) {
    let mut x = b.rng.random_range(3.0..8.0f32);
    while x < LENGTH - 3.0 {
        let w = b.rng.random_range(0.4..1.2f32);
        let h = b.rng.random_range(0.4..0.7f32);
        let z = b.rng.random_range(0.15..1.2f32);
        let depth = b.rng.random_range(0.06..0.12f32);
        let (y0, y1) = sorted(side * HALF_WIDTH, side * (HALF_WIDTH - depth));
        let p = b.prop_pattern();
        let m = b.material(p, 0.2, 0.9);
        b.prop(Object::aabb_box([x, y0, z], [x + w, y1, z + h], m));
        x += w + b.rng.random_range(6.0..14.0);
    }
}

/// Flush ceiling lights, 5 cm deep, every few metres.
fn lights(b: &mut SceneBuilder) {
    let m = b.material(Pattern::Plain, 0.85, 0.95);
    let mut x = 2.0;
    while x < LENGTH - 1.0 {
        b.prop(Object::aabb_box(
            [x, -0.2, HEIGHT - 0.05],
            [x + 1.2, 0.2, HEIGHT],
            m,
        ));
        x += b.rng.random_range(3.5..5.0);
    }
}

fn sorted(a: f32, b: f32) -> (f32, f32) {
    (a.min(b), a.max(b))
}
