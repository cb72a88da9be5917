//! FREAK's retina sampling pattern (Alahi, Ortiz, Vandergheynst, CVPR 2012) and its pair
//! tables.
//!
//! 43 receptive fields: seven concentric rings of six fields and one at the centre. Radii in
//! pattern units (multiplied by `pattern_scale` and the keypoint's scale to give pixels): the
//! outer ring at `R = 2/3`, the inner at `r = 1/12`, and between them the gaps shrink linearly
//! toward the centre — with `u = (R − r)/21`, ring `k` (outer first) lies at
//! `R − u·{0, 6, 11, 15, 18, 20, 21}[k]`, so consecutive gaps are 6, 5, 4, 3, 2, 1 units
//! (the paper's log-polar-like retina). Each field's size (the half-width of the averaging
//! square) is half its ring's radius, the centre's as the inner ring's — so fields overlap,
//! as the paper asks. Ring `k` has its six fields at angles `60°·j + 30°·(k mod 2)`:
//! odd rings are turned by half a step (hexagonal packing).
//!
//! Fields are numbered ring by ring from the outside (0–5 the outer ring, 36–41 the inner,
//! 42 the centre). The orientation uses 45 pairs on the five outer rings: on each, the three
//! pairs of opposite fields and the six pairs two steps apart (all symmetric about the
//! centre, as the paper's Fig. 6). The 512 descriptor pairs are chosen from all
//! 43·42/2 = 903 by the paper's greedy training ([`super::pairs_training`]); the table is
//! generated ([`super::freak_pairs`]).

/// Number of receptive fields.
pub const FIELDS: usize = 43;
/// Number of orientation pairs.
pub const ORIENTATION_PAIRS: usize = 45;
/// Number of descriptor pairs (512 bits).
pub const DESCRIPTOR_PAIRS: usize = 512;
/// Keypoint size (pixels) that the pattern at scale 1 describes.
pub const SMALLEST_KEYPOINT_SIZE: f32 = 7.0;

const OUTER: f64 = 2.0 / 3.0;
const INNER: f64 = 2.0 / 24.0;
const RING_STEPS: [f64; 7] = [0.0, 6.0, 11.0, 15.0, 18.0, 20.0, 21.0];

/// One receptive field in pattern units: centre offset and averaging half-width.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Field {
    pub x: f32,
    pub y: f32,
    pub sigma: f32,
}

/// The 43 receptive fields.
pub fn retina() -> [Field; FIELDS] {
    let unit = (OUTER - INNER) / 21.0;
    let mut fields = [Field {
        x: 0.0,
        y: 0.0,
        sigma: (INNER / 2.0) as f32,
    }; FIELDS];
    for (k, step) in RING_STEPS.iter().enumerate() {
        let radius = OUTER - unit * step;
        let turn = if k % 2 == 1 {
            std::f64::consts::PI / 6.0
        } else {
            0.0
        };
        for j in 0..6 {
            let a = std::f64::consts::PI / 3.0 * j as f64 + turn;
            fields[6 * k + j] = Field {
                x: (radius * a.cos()) as f32,
                y: (radius * a.sin()) as f32,
                sigma: (radius / 2.0) as f32,
            };
        }
    }
    fields
}

/// Outermost extent of any field (radius + half-width) in pattern units: `R + R/2 = 1`.
pub fn extent() -> f32 {
    (OUTER * 1.5) as f32
}

/// The 45 orientation pairs `(i, j)`.
pub fn orientation_pairs() -> [(u8, u8); ORIENTATION_PAIRS] {
    const OFFSETS: [(u8, u8); 9] = [
        (0, 3),
        (1, 4),
        (2, 5),
        (0, 2),
        (1, 3),
        (2, 4),
        (3, 5),
        (4, 0),
        (5, 1),
    ];
    let mut out = [(0, 0); ORIENTATION_PAIRS];
    for ring in 0..5u8 {
        for (n, (a, b)) in OFFSETS.iter().enumerate() {
            out[9 * ring as usize + n] = (6 * ring + a, 6 * ring + b);
        }
    }
    out
}

/// All 903 field pairs `(i, j)` with `i > j`, in order of `i` then `j`: the candidates of
/// the pair training, indexed by [`pair_index`].
pub fn all_pairs() -> Vec<(u8, u8)> {
    let mut out = Vec::with_capacity(FIELDS * (FIELDS - 1) / 2);
    for i in 1..FIELDS as u8 {
        for j in 0..i {
            out.push((i, j));
        }
    }
    out
}

/// Index of pair `(i, j)`, `i > j`, in [`all_pairs`].
pub fn pair_index(i: usize, j: usize) -> usize {
    i * (i - 1) / 2 + j
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rings_have_six_fields_at_their_radius() {
        let f = retina();
        let r = |p: &Field| (p.x * p.x + p.y * p.y).sqrt();
        for ring in f[..42].chunks(6) {
            let r0 = r(&ring[0]);
            assert!(ring.iter().all(|p| (r(p) - r0).abs() < 1e-6));
            assert!(ring.iter().all(|p| (p.sigma - r0 / 2.0).abs() < 1e-6));
        }
        assert!((r(&f[0]) - 2.0 / 3.0).abs() < 1e-6);
        assert!((r(&f[36]) - 1.0 / 12.0).abs() < 1e-6);
        assert_eq!((f[42].x, f[42].y), (0.0, 0.0));
        // Odd rings are turned by 30°.
        assert!((f[6].y.atan2(f[6].x).to_degrees() - 30.0).abs() < 1e-4);
        assert!((extent() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn orientation_pairs_are_distinct_and_on_one_ring() {
        let p = orientation_pairs();
        let mut seen = std::collections::BTreeSet::new();
        for (a, b) in p {
            assert_ne!(a, b);
            assert_eq!(a / 6, b / 6);
            assert!(a < 30 && b < 30);
            assert!(seen.insert((a.min(b), a.max(b))));
        }
    }

    #[test]
    fn pair_index_inverts_all_pairs() {
        let all = all_pairs();
        assert_eq!(all.len(), 903);
        for (k, (i, j)) in all.iter().enumerate() {
            assert_eq!(pair_index(*i as usize, *j as usize), k);
        }
    }
}
