//! Collects a scene's objects and keeps the trajectory in free space.

use parry3d::math::Vector as GVec;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::motion::Motion;
use crate::texture::{Material, Pattern};
use crate::world::{Object, World};
use crate::SimError;

/// Spacing of the trajectory samples checked for clearance, metres.
const SAMPLE_STEP_M: f64 = 0.25;

/// Accumulates objects; props too close to the trajectory are dropped at the end.
pub(crate) struct SceneBuilder {
    /// The scene's random stream (layout, materials).
    pub rng: ChaCha8Rng,
    /// `(object, is_structure)`: structure (walls, floor) is never dropped.
    objects: Vec<(Object, bool)>,
    /// Minimum distance kept between the sensor and any object, metres.
    margin: f32,
}

impl SceneBuilder {
    /// A builder seeded from `seed` and a per-scene `salt`.
    pub fn new(seed: u64, salt: u64, margin: f32) -> Self {
        Self {
            rng: ChaCha8Rng::seed_from_u64(seed ^ salt.wrapping_mul(0x9E37_79B9_7F4A_7C15)),
            objects: Vec::new(),
            margin,
        }
    }

    /// A material with `pattern`, a base albedo drawn in `lo..hi` and a fresh seed.
    pub fn material(&mut self, pattern: Pattern, lo: f32, hi: f32) -> Material {
        let base = self.rng.random_range(lo..hi);
        let seed = self.rng.random::<u64>();
        Material::new(pattern, base, seed)
    }

    /// A random wall-like pattern (posters, stripes, blobs or tiles).
    pub fn wall_pattern(&mut self) -> Pattern {
        match self.rng.random_range(0..4) {
            0 => Pattern::Stripes {
                width: self.rng.random_range(0.2..0.5),
            },
            1 => Pattern::Blobs {
                cell: self.rng.random_range(0.6..1.2),
            },
            2 => Pattern::Tiles {
                cell: self.rng.random_range(0.3..0.7),
            },
            _ => Pattern::Posters {
                cell_u: self.rng.random_range(1.0..1.8),
                cell_v: self.rng.random_range(0.9..1.4),
                density: self.rng.random_range(0.4..0.8),
            },
        }
    }

    /// A random prop pattern, smaller-scaled than [`Self::wall_pattern`].
    pub fn prop_pattern(&mut self) -> Pattern {
        match self.rng.random_range(0..4) {
            0 => Pattern::Stripes {
                width: self.rng.random_range(0.08..0.2),
            },
            1 => Pattern::Blobs {
                cell: self.rng.random_range(0.3..0.6),
            },
            2 => Pattern::Tiles {
                cell: self.rng.random_range(0.15..0.35),
            },
            _ => Pattern::Posters {
                cell_u: self.rng.random_range(0.4..0.8),
                cell_v: self.rng.random_range(0.4..0.8),
                density: 0.7,
            },
        }
    }

    /// Left (1) or right (−1) of the path, at random.
    pub fn random_side(&mut self) -> f64 {
        if self.rng.random_bool(0.5) {
            1.0
        } else {
            -1.0
        }
    }

    /// Adds structure (never dropped; the trajectory must clear it).
    pub fn structure(&mut self, o: Object) {
        self.objects.push((o, true));
    }

    /// Adds a prop (dropped if it comes within the margin of the trajectory).
    pub fn prop(&mut self, o: Object) {
        self.objects.push((o, false));
    }

    /// Drops props near the trajectory, checks the structure, and builds the [`World`].
    pub fn finish(self, scene: &'static str, motion: &Motion) -> Result<World, SimError> {
        let samples = trajectory_samples(motion);
        let margin = self.margin;
        let mut kept = Vec::with_capacity(self.objects.len());
        for (o, is_structure) in self.objects {
            let too_close = near(&o, &samples, margin);
            if too_close && is_structure {
                return Err(SimError::Scene {
                    scene,
                    message: "the trajectory comes within the margin of a wall".into(),
                });
            }
            if !too_close {
                kept.push(o);
            }
        }
        Ok(World::new(kept))
    }
}

/// Sensor positions along one lap, independent of the speed (the bob is within the margin).
fn trajectory_samples(motion: &Motion) -> Vec<GVec> {
    let lap = motion.lap_length();
    let n = (lap / SAMPLE_STEP_M).ceil().max(1.0) as usize;
    let z = motion.height() as f32;
    (0..n)
        .map(|k| {
            let q = motion.position_at_distance(lap * k as f64 / n as f64);
            GVec::new(q.x as f32, q.y as f32, z)
        })
        .collect()
}

/// Whether any sample lies within `margin` of `o` (AABB pre-test, then exact distance).
fn near(o: &Object, samples: &[GVec], margin: f32) -> bool {
    let aabb = o.aabb();
    let (lo, hi) = (
        aabb.mins - GVec::splat(margin),
        aabb.maxs + GVec::splat(margin),
    );
    samples
        .iter()
        .any(|p| p.cmpge(lo).all() && p.cmple(hi).all() && o.distance(*p) < margin)
}
