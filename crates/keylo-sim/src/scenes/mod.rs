//! The synthetic worlds and their ground-truth motion, built from a seed.

mod builder;
mod corridor;
mod lab;
mod park;
mod path_frame;
mod road;

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
            let s = Scene::build(kind, 5, 1.0, 1.0, Appearance::Ideal).unwrap();
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
