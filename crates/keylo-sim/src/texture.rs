//! Procedural surface textures: albedo as a function of a face's `(u, v)` coordinates.
//!
//! Patterns are evaluated in each object's own coordinates, so they stay fixed in the world
//! between frames, and are hashed from the object's seed, so every object looks different.
//! They are built from cells (posters, tiles, windows, blobs, stripe segments): cell corners
//! and blob centres are what keypoint detectors find in the signal and reflectivity images.

use crate::noise::{hash_words, unit};

/// Albedo of retro-reflective surfaces (reflectivity ≈ 100 · albedo, above 100).
pub const RETRO_ALBEDO: f32 = 2.0;

/// A procedural albedo pattern; lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pattern {
    /// Uniform albedo with a gentle low-frequency variation.
    Plain,
    /// Rectangular posters with a block layout, in a fraction `density` of the cells.
    Posters {
        /// Cell width.
        cell_u: f32,
        /// Cell height.
        cell_v: f32,
        /// Fraction of cells holding a poster.
        density: f32,
    },
    /// Tiles of random albedo separated by darker grout (checker-like patches).
    Tiles {
        /// Tile size.
        cell: f32,
    },
    /// Floor tiles of one material: each tile's albedo a little off the background's
    /// (`± contrast` of it) and mottled at a tenth of the tile size (wear, dirt, gloss),
    /// with thin grout lines a little darker; in a share `flecks` of its 0.1 m cells a small
    /// bright fleck (3–7 cm across, four times the albedo). A real hall's floor seen at
    /// grazing angles shows them as short bright streaks one row high that stay put from
    /// frame to frame (docs/results/sim-realism.md).
    Flooring {
        /// Tile size.
        cell: f32,
        /// How far a tile's albedo is off the background's (share of it).
        contrast: f32,
        /// Share of the 0.1 m cells holding a bright fleck (0: none).
        flecks: f32,
    },
    /// One material with a fine mottle (gravel, soil, grass): albedo `± contrast` of the
    /// background's, varying smoothly over `cell`.
    Mottled {
        /// Size of a mottle.
        cell: f32,
        /// How far the albedo strays from the background's (share of it).
        contrast: f32,
    },
    /// Vertical stripes of random albedo, broken at staggered heights.
    Stripes {
        /// Stripe width.
        width: f32,
    },
    /// One soft disc (bright or dark) per cell.
    Blobs {
        /// Cell size.
        cell: f32,
    },
    /// A facade: a grid of framed windows, dark or lit.
    Windows {
        /// Horizontal window pitch.
        cell_u: f32,
        /// Vertical window pitch.
        cell_v: f32,
    },
    /// Asphalt with dashed lane lines at `v = ±1.8` and edge lines at `|v| ≈ 6.4`.
    Road,
}

/// The optical properties of one object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// The albedo pattern.
    pub pattern: Pattern,
    /// Background albedo, 0..1.
    pub base: f32,
    /// Seed of this object's pattern.
    pub seed: u64,
    /// Factor from albedo to near-infrared (ambient) reflectance.
    pub nir_gain: f32,
}

impl Material {
    /// A material with `pattern` and `base` albedo; `seed` individualises it.
    pub fn new(pattern: Pattern, base: f32, seed: u64) -> Self {
        let nir_gain = 0.6 + 0.8 * unit(hash_words(&[seed, 0x4E1B]));
        Self {
            pattern,
            base,
            seed,
            nir_gain,
        }
    }

    /// Albedo at `(u, v)` of face `face`: 0.02..1 for diffuse surfaces, up to
    /// [`RETRO_ALBEDO`] for retro-reflectors.
    pub fn albedo(&self, face: u32, u: f32, v: f32) -> f32 {
        let seed = hash_words(&[self.seed, face as u64]);
        let raw = match self.pattern {
            Pattern::Plain => self.base,
            Pattern::Posters {
                cell_u,
                cell_v,
                density,
            } => posters(seed, self.base, (cell_u, cell_v, density), u, v),
            Pattern::Tiles { cell } => tiles(seed, self.base, cell, u, v),
            Pattern::Flooring {
                cell,
                contrast,
                flecks,
            } => flooring(seed, self.base, (cell, contrast, flecks), u, v),
            Pattern::Mottled { cell, contrast } => {
                self.base * mottle(seed, contrast, u / cell, v / cell)
            }
            Pattern::Stripes { width } => stripes(seed, width, u, v),
            Pattern::Blobs { cell } => blobs(seed, self.base, cell, u, v),
            Pattern::Windows { cell_u, cell_v } => windows(seed, self.base, cell_u, cell_v, u, v),
            Pattern::Road => road(seed, self.base, u, v),
        };
        if raw > 1.0 {
            return raw;
        }
        (raw * (0.85 + 0.3 * value_noise(seed, u * 0.5, v * 0.5))).clamp(0.02, 1.0)
    }
}

/// Smooth value noise in `[0, 1]`, unit lattice.
fn value_noise(seed: u64, x: f32, y: f32) -> f32 {
    let (i, j) = (x.floor(), y.floor());
    let (fx, fy) = (x - i, y - j);
    let (sx, sy) = (fx * fx * (3.0 - 2.0 * fx), fy * fy * (3.0 - 2.0 * fy));
    let corner = |di: f32, dj: f32| unit(cell_hash(seed, 7, i + di, j + dj));
    let top = corner(0.0, 0.0) + (corner(1.0, 0.0) - corner(0.0, 0.0)) * sx;
    let bottom = corner(0.0, 1.0) + (corner(1.0, 1.0) - corner(0.0, 1.0)) * sx;
    top + (bottom - top) * sy
}

/// Hash of the lattice cell `(i, j)` (given as floored floats) under `seed` and `salt`.
fn cell_hash(seed: u64, salt: u64, i: f32, j: f32) -> u64 {
    hash_words(&[seed, salt, i as i64 as u64, j as i64 as u64])
}

/// Cell indices and the position inside the cell, normalised to `[0, 1)`.
fn cell_of(u: f32, v: f32, cu: f32, cv: f32) -> (f32, f32, f32, f32) {
    let (i, j) = ((u / cu).floor(), (v / cv).floor());
    (i, j, u / cu - i, v / cv - j)
}

fn posters(seed: u64, base: f32, (cu, cv, density): (f32, f32, f32), u: f32, v: f32) -> f32 {
    let (i, j, fu, fv) = cell_of(u, v, cu, cv);
    let h = cell_hash(seed, 1, i, j);
    if unit(h) >= density {
        return base;
    }
    let r = |k: u64| unit(hash_words(&[h, k]));
    let (u0, u1) = (0.05 + 0.25 * r(1), 0.95 - 0.25 * r(2));
    let (v0, v1) = (0.05 + 0.25 * r(3), 0.95 - 0.25 * r(4));
    if fu < u0 || fu >= u1 || fv < v0 || fv >= v1 {
        return base;
    }
    if r(5) < 0.08 {
        return RETRO_ALBEDO;
    }
    let bu = ((fu - u0) / (u1 - u0) * 3.0).floor() as u64;
    let bv = ((fv - v0) / (v1 - v0) * 4.0).floor() as u64;
    0.05 + 0.9 * unit(hash_words(&[h, 10 + bu, 20 + bv]))
}

fn tiles(seed: u64, base: f32, cell: f32, u: f32, v: f32) -> f32 {
    let (i, j, fu, fv) = cell_of(u, v, cell, cell);
    let grout = 0.04 / cell;
    if fu < grout || fv < grout {
        return base * 0.5;
    }
    0.12 + 0.76 * unit(cell_hash(seed, 2, i, j))
}

/// Cell size and albedo gain of the floor's bright flecks.
const FLECK_CELL_M: f32 = 0.1;
const FLECK_GAIN: f32 = 4.0;

fn flooring(
    seed: u64,
    base: f32,
    (cell, contrast, flecks): (f32, f32, f32),
    u: f32,
    v: f32,
) -> f32 {
    let (i, j, fu, fv) = cell_of(u, v, cell, cell);
    let grout = 0.01 / cell;
    if fu < grout || fv < grout {
        return base * 0.8;
    }
    let tile = 2.0 * unit(cell_hash(seed, 9, i, j)) - 1.0;
    let albedo =
        base * (1.0 + contrast * tile) * mottle(seed, contrast, 10.0 * u / cell, 10.0 * v / cell);
    if flecks > 0.0 && in_fleck(seed, flecks, u, v) {
        return (albedo * FLECK_GAIN).min(1.0);
    }
    albedo
}

/// Whether `(u, v)` lies on a fleck: a disc of radius 0.15–0.35 cells, somewhere in the
/// middle of its cell, in a share `share` of the cells.
fn in_fleck(seed: u64, share: f32, u: f32, v: f32) -> bool {
    let (i, j, fu, fv) = cell_of(u, v, FLECK_CELL_M, FLECK_CELL_M);
    let h = cell_hash(seed, 11, i, j);
    if unit(h) >= share {
        return false;
    }
    let r = |k: u64| unit(hash_words(&[h, k]));
    let (cx, cy, radius) = (0.3 + 0.4 * r(1), 0.3 + 0.4 * r(2), 0.15 + 0.2 * r(3));
    (fu - cx).powi(2) + (fv - cy).powi(2) < radius * radius
}

/// A factor `1 ± contrast` varying smoothly over the unit lattice of `(x, y)`.
fn mottle(seed: u64, contrast: f32, x: f32, y: f32) -> f32 {
    1.0 + contrast * (2.0 * value_noise(seed ^ 0x3077, x, y) - 1.0)
}

fn stripes(seed: u64, width: f32, u: f32, v: f32) -> f32 {
    let k = (u / width).floor();
    let offset = 1.5 * unit(cell_hash(seed, 3, k, 0.0));
    let seg = ((v + offset) / 1.5).floor();
    0.08 + 0.84 * unit(cell_hash(seed, 4, k, seg))
}

fn blobs(seed: u64, base: f32, cell: f32, u: f32, v: f32) -> f32 {
    let (i, j, fu, fv) = cell_of(u, v, cell, cell);
    let h = cell_hash(seed, 5, i, j);
    let r = |k: u64| unit(hash_words(&[h, k]));
    let (cx, cy) = (0.3 + 0.4 * r(1), 0.3 + 0.4 * r(2));
    let radius = 0.12 + 0.16 * r(3);
    let d = ((fu - cx).powi(2) + (fv - cy).powi(2)).sqrt();
    let inner = 0.6 * radius;
    let w = if d <= inner {
        1.0
    } else if d >= radius {
        0.0
    } else {
        let t = (radius - d) / (radius - inner);
        t * t * (3.0 - 2.0 * t)
    };
    let target = if r(4) < 0.5 { 0.04 } else { 0.95 };
    base + (target - base) * w
}

fn windows(seed: u64, base: f32, cu: f32, cv: f32, u: f32, v: f32) -> f32 {
    let (i, j, fu, fv) = cell_of(u, v, cu, cv);
    let (u0, u1, v0, v1) = (0.22, 0.78, 0.25, 0.8);
    let frame_u = 0.08 / cu;
    let frame_v = 0.08 / cv;
    let inside = |m: f32| fu >= u0 - m && fu < u1 + m && fv >= v0 - m && fv < v1 + m;
    if fu >= u0 && fu < u1 && fv >= v0 && fv < v1 {
        let h = cell_hash(seed, 6, i, j);
        return if unit(h) < 0.3 { 0.55 } else { 0.05 };
    }
    if inside(frame_u.max(frame_v)) {
        return 0.9;
    }
    base
}

fn road(seed: u64, base: f32, u: f32, v: f32) -> f32 {
    let lane = (v.abs() - 1.8).abs() < 0.075 && (u / 9.0).rem_euclid(1.0) < 0.33;
    if lane {
        return 1.6;
    }
    if (v.abs() - 6.4).abs() < 0.08 {
        return 0.85;
    }
    let patch = unit(cell_hash(seed, 8, (u / 2.0).floor(), (v / 2.0).floor()));
    base * (0.75 + 0.5 * patch)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [Pattern; 9] = [
        Pattern::Plain,
        Pattern::Posters {
            cell_u: 1.5,
            cell_v: 1.2,
            density: 0.6,
        },
        Pattern::Tiles { cell: 0.6 },
        Pattern::Flooring {
            cell: 0.6,
            contrast: 0.3,
            flecks: 0.3,
        },
        Pattern::Mottled {
            cell: 0.2,
            contrast: 0.4,
        },
        Pattern::Stripes { width: 0.3 },
        Pattern::Blobs { cell: 0.8 },
        Pattern::Windows {
            cell_u: 3.0,
            cell_v: 3.2,
        },
        Pattern::Road,
    ];

    fn sample(m: &Material) -> Vec<f32> {
        (0..400)
            .map(|k| m.albedo(0, (k % 20) as f32 * 0.37, (k / 20) as f32 * 0.29))
            .collect()
    }

    #[test]
    fn albedo_is_bounded_and_textured() {
        for p in ALL {
            let m = Material::new(p, 0.5, 42);
            let a = sample(&m);
            assert!(a.iter().all(|x| (0.02..=RETRO_ALBEDO).contains(x)), "{p:?}");
            let (lo, hi) = a
                .iter()
                .fold((9.0f32, 0.0f32), |(l, h), x| (l.min(*x), h.max(*x)));
            let needed = if p == Pattern::Plain { 0.02 } else { 0.2 };
            assert!(hi - lo > needed, "{p:?}: {lo}..{hi}");
        }
    }

    #[test]
    fn seeds_change_the_texture() {
        let p = Pattern::Tiles { cell: 0.6 };
        let a = sample(&Material::new(p, 0.5, 1));
        let b = sample(&Material::new(p, 0.5, 2));
        assert_ne!(a, b);
        assert_eq!(a, sample(&Material::new(p, 0.5, 1)));
    }
}
