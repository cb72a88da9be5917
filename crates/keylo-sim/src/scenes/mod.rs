//! The synthetic worlds and their ground-truth motion, built from a seed.

mod builder;
mod corridor;
mod hall;
mod lab;
mod park;
mod path_frame;
mod road;
mod shapes;

use parry3d::math::Vector as GVec;

use crate::motion::Motion;
use crate::world::World;
use crate::{Appearance, SceneKind, SimError};

pub(crate) use builder::SceneBuilder;

/// Ambient (near-infrared) illumination of a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ambient {
    /// Unit direction towards the main light (the sun outdoors, the ceiling lights indoors).
    pub light_dir: GVec,
    /// Near-IR counts of a white surface facing the light.
    pub direct: f32,
    /// Near-IR counts of a white surface from diffuse (sky / room) light.
    pub diffuse: f32,
    /// Near-IR counts of pixels that see no surface (the sky); 0 indoors.
    pub sky: f32,
}

/// A world, the sensor's motion through it and its lighting.
#[derive(Debug)]
pub struct Scene {
    /// Which scene this is.
    pub kind: SceneKind,
    /// The static geometry.
    pub world: World,
    /// The sensor's ground-truth motion (world frame).
    pub motion: Motion,
    /// Ambient light for the near-IR channel.
    pub ambient: Ambient,
}

impl Scene {
    /// Builds `kind` from `seed`, the sensor moving at `speed_scale` × the nominal speed.
    pub fn build(
        kind: SceneKind,
        seed: u64,
        speed_scale: f64,
        sway_scale: f64,
        look: Appearance,
    ) -> Result<Self, SimError> {
        let (builder, motion, ambient) = match kind {
            SceneKind::Lab => lab::build(seed, speed_scale, look),
            SceneKind::Corridor => corridor::build(seed, speed_scale),
            SceneKind::Road => road::build(seed, speed_scale),
            SceneKind::Park => park::build(seed, speed_scale),
        };
        let motion = motion.with_sway_scaled(sway_scale);
        let world = builder.finish(kind.name(), &motion)?;
        Ok(Self {
            kind,
            world,
            motion,
            ambient,
        })
    }
}

/// Indoor lighting: ceiling lights.
fn indoor_light() -> Ambient {
    Ambient {
        light_dir: GVec::new(0.15, 0.1, 1.0).normalize(),
        direct: 120.0,
        diffuse: 60.0,
        sky: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scene_builds_and_keeps_the_path_clear() {
        for kind in [
            SceneKind::Lab,
            SceneKind::Corridor,
            SceneKind::Road,
            SceneKind::Park,
        ] {
            for look in [Appearance::Ideal, Appearance::Ouster] {
                path_is_clear(&Scene::build(kind, 5, 1.0, 1.0, look).unwrap());
            }
        }
    }

    fn path_is_clear(s: &Scene) {
        let kind = s.kind;
        assert!(s.world.objects().len() > 20, "{kind:?}");
        let lap = s.motion.lap_length();
        let n = 400;
        for k in 0..n {
            let t = lap / s.motion.speed() * k as f64 / n as f64;
            let p = s.motion.pose_at(t).translation.vector.cast::<f32>();
            let c = s.world.clearance(GVec::new(p.x, p.y, p.z));
            assert!(c > 0.25, "{kind:?} at t={t}: clearance {c}");
        }
    }

    /// The `ouster` hall has things taller than the sensor within a few metres of the path
    /// (the real images' corners above the horizon sit on such things); `ideal` has only its
    /// pillar and column there.
    #[test]
    fn the_ouster_hall_has_tall_things_near_the_path() {
        let near_and_tall = |look| {
            let s = Scene::build(SceneKind::Lab, 3, 1.0, 0.0, look).unwrap();
            let lap = s.motion.lap_length();
            let path: Vec<_> = (0..200)
                .map(|k| s.motion.position_at_distance(lap * k as f64 / 200.0))
                .collect();
            let top = s.motion.height() as f32 + 0.3;
            s.world
                .objects()
                .iter()
                .filter(|o| {
                    let b = o.aabb();
                    let c = b.center();
                    b.maxs.z > top
                        && b.maxs.z < 4.0
                        && path.iter().any(|p| {
                            let (dx, dy) = (c.x - p.x as f32, c.y - p.y as f32);
                            (dx * dx + dy * dy).sqrt() < 2.0
                        })
                })
                .count()
        };
        let (ideal, ouster) = (
            near_and_tall(Appearance::Ideal),
            near_and_tall(Appearance::Ouster),
        );
        assert!(ouster >= ideal + 15, "ideal: {ideal}, ouster: {ouster}");
    }

    #[test]
    fn seeds_change_the_layout() {
        let a = Scene::build(SceneKind::Lab, 1, 1.0, 1.0, Appearance::Ideal).unwrap();
        let b = Scene::build(SceneKind::Lab, 2, 1.0, 1.0, Appearance::Ideal).unwrap();
        assert_ne!(a.world.objects(), b.world.objects());
        let c = Scene::build(SceneKind::Lab, 1, 1.0, 1.0, Appearance::Ideal).unwrap();
        assert_eq!(a.world.objects(), c.world.objects());
    }
}
