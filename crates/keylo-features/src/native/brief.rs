//! `brief`: the BRIEF binary descriptor (Calonder et al., ECCV 2010), native.
//!
//! Each bit compares the smoothed intensities of two points of a 48×48 patch around the
//! keypoint: 1 when the first is darker. Smoothing is a 9×9 box sum from an integral image
//! (the approximation of the paper's Gaussian that OpenCV's BRIEF also uses). Two test
//! patterns, both from the paper's best "G II" layout (isotropic Gaussian, `σ² = S²/25`,
//! `S = 48`):
//! - `opencv` (default): OpenCV contrib's own pattern ([`super::brief_opencv`], measured from
//!   its behaviour), so the descriptors are OpenCV's bit for bit, as the paper's authors had;
//! - `gaussian`: keylo's own draw, by a fixed-seed generator ([`test_pairs`]).
//!
//! Keypoints are placed as OpenCV places them: dropped when their rounded position is within
//! 28 pixels of a border; with `use_orientation`, each test offset turned by the keypoint's
//! angle, truncated to whole pixels and clamped to the patch.

use keylo_core::{CoreError, Descriptor, Descriptors, Image, Keypoint};
use rand::RngCore;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::input::{binary, one_plane};
use super::Integral;
use crate::{check, FeaturesError};

/// Side of the patch the test points are drawn from, pixels.
pub const PATCH_SIZE: i32 = 48;
/// Side of the smoothing box, pixels.
pub const KERNEL_SIZE: i32 = 9;
/// Seed of the test-pair generator (ASCII "keyloBRF").
pub const SEED: u64 = 0x6b65_796c_6f42_5246;

const HALF_PATCH: i32 = PATCH_SIZE / 2;
const HALF_KERNEL: i32 = KERNEL_SIZE / 2;
/// Keypoints nearer than this to a border are not described.
const BORDER: i32 = HALF_PATCH + HALF_KERNEL;

/// Which test pattern `brief` uses.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum BriefPattern {
    /// OpenCV contrib's pattern: OpenCV's descriptors bit for bit.
    #[default]
    Opencv,
    /// keylo's own fixed-seed Gaussian draw.
    Gaussian,
}

/// `[descriptor] kind = "brief"` (the defaults of OpenCV contrib's `BriefDescriptorExtractor`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct BriefParams {
    /// Descriptor length in bytes: 16, 32 or 64 (128, 256 or 512 tests).
    pub bytes: usize,
    /// Rotate the test pattern by each keypoint's angle (as OpenCV: every keypoint, an angle
    /// of -1 included).
    pub use_orientation: bool,
    /// `opencv` (OpenCV contrib's test pattern) or `gaussian` (keylo's own draw).
    pub pattern: BriefPattern,
}

impl Default for BriefParams {
    fn default() -> Self {
        Self {
            bytes: 32,
            use_orientation: false,
            pattern: BriefPattern::Opencv,
        }
    }
}

/// One test: compare the smoothed intensity at `a` with that at `b` (offsets from the keypoint).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TestPair {
    pub a: (i32, i32),
    pub b: (i32, i32),
}

/// A uniform number in (0, 1] from the top 53 bits of one 64-bit draw.
fn unit(rng: &mut ChaCha8Rng) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 1.0) / (1u64 << 53) as f64
}

/// Two independent standard normals (Box–Muller on two draws).
fn normals(rng: &mut ChaCha8Rng) -> (f64, f64) {
    let (u, v) = (unit(rng), unit(rng));
    let r = (-2.0 * u.ln()).sqrt();
    let t = 2.0 * std::f64::consts::PI * v;
    (r * t.cos(), r * t.sin())
}

/// `n` test pairs from ChaCha8 seeded with `seed`: each coordinate `N(0, S²/25)` rounded and
/// clipped to `[-S/2, S/2]`. Shorter descriptors use a prefix of the same sequence.
pub fn test_pairs(n: usize, seed: u64) -> Vec<TestPair> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let sigma = f64::from(PATCH_SIZE) / 5.0;
    let coord = |rng: &mut ChaCha8Rng| {
        let (a, b) = normals(rng);
        let c = |z: f64| ((z * sigma).round() as i32).clamp(-HALF_PATCH, HALF_PATCH);
        (c(a), c(b))
    };
    (0..n)
        .map(|_| TestPair {
            a: coord(&mut rng),
            b: coord(&mut rng),
        })
        .collect()
}

/// The native BRIEF descriptor.
pub struct Brief {
    bytes: usize,
    use_orientation: bool,
    pairs: Vec<TestPair>,
    /// Offsets of the upright tests in smoothed images of width `upright_width`.
    upright: Vec<[isize; 2]>,
    upright_width: usize,
    /// The current keypoint's turned tests.
    turned: Vec<[isize; 2]>,
}

/// Offset in the smoothed image of width `width` from a keypoint's pixel to the centre
/// of its test box at `(dx, dy)`.
fn offset((dx, dy): (i32, i32), width: isize) -> isize {
    dy as isize * width + dx as isize
}

impl Brief {
    /// Checks `params` and samples the test pattern.
    pub fn new(params: &BriefParams) -> Result<Self, FeaturesError> {
        check(
            matches!(params.bytes, 16 | 32 | 64),
            "bytes",
            params.bytes,
            "expected 16, 32 or 64",
        )?;
        Ok(Self {
            bytes: params.bytes,
            use_orientation: params.use_orientation,
            pairs: match params.pattern {
                BriefPattern::Opencv => super::brief_opencv::PAIRS[..params.bytes * 8]
                    .iter()
                    .map(|&[ax, ay, bx, by]| TestPair {
                        a: (i32::from(ax), i32::from(ay)),
                        b: (i32::from(bx), i32::from(by)),
                    })
                    .collect(),
                BriefPattern::Gaussian => test_pairs(params.bytes * 8, SEED),
            },
            upright: Vec::new(),
            upright_width: 0,
            turned: Vec::with_capacity(params.bytes * 8),
        })
    }

    /// The test pattern (unrotated).
    pub fn pairs(&self) -> &[TestPair] {
        &self.pairs
    }

    /// `kp`'s pixel index and its tests' offsets (turned when configured), or `None` when it
    /// lies within `BORDER` of an edge of the `w × h` image. As OpenCV: the border test on the
    /// position rounded half to even, the tests around it rounded half up.
    fn place(&mut self, kp: &Keypoint, w: i32, h: i32) -> Option<(usize, &[[isize; 2]])> {
        let (bx, by) = (kp.x.round_ties_even(), kp.y.round_ties_even());
        let border = BORDER as f32;
        if !(bx >= border && by >= border && bx < (w - BORDER) as f32 && by < (h - BORDER) as f32) {
            return None;
        }
        let (x, y) = ((kp.x + 0.5) as i32, (kp.y + 0.5) as i32);
        let width = w as isize;
        let entry = (y as isize * width + x as isize) as usize;
        if !self.use_orientation {
            return Some((entry, self.upright.as_slice()));
        }
        let angle = kp.angle * (std::f64::consts::PI / 180.0) as f32;
        let (s, c) = (angle.sin(), angle.cos());
        let turn = |(dx, dy): (i32, i32)| {
            let (dx, dy) = (dx as f32, dy as f32);
            let clamp = |v: f32| (v as i32).clamp(-HALF_PATCH, HALF_PATCH);
            (clamp(dx * c - dy * s), clamp(dx * s + dy * c))
        };
        self.turned.clear();
        for p in &self.pairs {
            self.turned
                .push([offset(turn(p.a), width), offset(turn(p.b), width)]);
        }
        Some((entry, self.turned.as_slice()))
    }

    /// Descriptors of `keypoints`, dropping those too close to a border.
    pub fn compute(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, FeaturesError> {
        one_plane("brief", image)?;
        let smooth = Integral::new(image).box_sums(HALF_KERNEL as usize);
        if self.upright_width != image.width {
            let width = image.width as isize;
            self.upright = self
                .pairs
                .iter()
                .map(|p| [offset(p.a, width), offset(p.b, width)])
                .collect();
            self.upright_width = image.width;
        }
        let (w, h) = (image.width as i32, image.height as i32);
        let bytes = self.bytes;
        let mut data = Vec::with_capacity(keypoints.len() * bytes);
        keypoints.retain(|kp| {
            let Some((entry, tests)) = self.place(kp, w, h) else {
                return false;
            };
            let at = |o: isize| smooth[entry.wrapping_add_signed(o)];
            // Bit k of the row is test k, most significant bit of each byte first.
            data.extend(tests.chunks_exact(8).map(|eight| {
                eight
                    .iter()
                    .fold(0u8, |byte, [a, b]| (byte << 1) | u8::from(at(*a) < at(*b)))
            }));
            true
        });
        Ok(binary(bytes, data))
    }
}

impl Descriptor for Brief {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        self.compute(image, keypoints)
            .map_err(|e| e.in_stage("descriptor"))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_images::{blobs, hamming, keypoint};
    use super::*;
    use keylo_core::DescriptorData;

    fn rows(d: &Descriptors) -> Vec<&[u8]> {
        match &d.data {
            DescriptorData::Binary(b) => b.chunks(d.dim).collect(),
            DescriptorData::Float(_) => panic!("float descriptors"),
        }
    }

    #[test]
    fn test_pairs_are_deterministic_gaussian_and_in_the_patch() {
        let p = test_pairs(512, SEED);
        assert_eq!(p, test_pairs(512, SEED));
        assert_eq!(&p[..128], &test_pairs(128, SEED)[..]);
        assert_ne!(p, test_pairs(512, SEED + 1));
        let coords: Vec<f64> = p
            .iter()
            .flat_map(|t| [t.a.0, t.a.1, t.b.0, t.b.1])
            .map(f64::from)
            .collect();
        assert!(coords.iter().all(|c| c.abs() <= 24.0));
        let mean = coords.iter().sum::<f64>() / coords.len() as f64;
        let sd = (coords.iter().map(|c| c * c).sum::<f64>() / coords.len() as f64).sqrt();
        assert!(mean.abs() < 0.6, "mean {mean}");
        assert!((sd - 9.6).abs() < 0.5, "sd {sd} (expected S/5 = 9.6)");
    }

    #[test]
    fn drops_border_keypoints_and_keeps_rows_aligned() {
        let img = blobs(120, 64, 60.0, 32.0, 0.0);
        let mut b = Brief::new(&BriefParams::default()).unwrap();
        let mut kps = vec![
            keypoint(27.0, 32.0),
            keypoint(60.0, 32.0),
            keypoint(60.0, 36.0),
            keypoint(40.0, 30.0),
            keypoint(91.0, 28.0),
        ];
        let d = b.compute(&img, &mut kps).unwrap();
        let xy: Vec<(f32, f32)> = kps.iter().map(|k| (k.x, k.y)).collect();
        assert_eq!(xy, vec![(60.0, 32.0), (40.0, 30.0), (91.0, 28.0)]);
        assert_eq!((d.rows, d.dim), (3, 32));
        // Row i describes keypoints[i]: describing one alone gives the same row.
        let mut one = vec![keypoint(40.0, 30.0)];
        let d1 = b.compute(&img, &mut one).unwrap();
        assert_eq!(rows(&d)[1], rows(&d1)[0]);
    }

    #[test]
    fn same_point_twice_is_distance_zero_and_others_differ() {
        let img = blobs(120, 64, 60.0, 32.0, 0.0);
        for bytes in [16, 32, 64] {
            let mut b = Brief::new(&BriefParams {
                bytes,
                ..BriefParams::default()
            })
            .unwrap();
            let mut kps = vec![
                keypoint(50.0, 32.0),
                keypoint(50.0, 32.0),
                keypoint(70.0, 33.0),
            ];
            let d = b.compute(&img, &mut kps).unwrap();
            let r = rows(&d);
            assert_eq!(d.dim, bytes);
            assert_eq!(hamming(r[0], r[1]), 0);
            assert!(hamming(r[0], r[2]) > bytes as u32);
        }
    }

    #[test]
    fn oriented_pattern_follows_the_keypoint_angle() {
        let (cx, cy) = (60.0, 32.0);
        let up = blobs(120, 64, cx, cy, 0.0);
        let turned = blobs(120, 64, cx, cy, 20.0);
        let mut b = Brief::new(&BriefParams {
            use_orientation: true,
            ..BriefParams::default()
        })
        .unwrap();
        let mut k0 = vec![Keypoint {
            angle: 0.0,
            ..keypoint(cx, cy)
        }];
        let mut k1 = vec![Keypoint {
            angle: 20.0,
            ..keypoint(cx, cy)
        }];
        let mut k1_unturned = k0.clone();
        let (d0, d1) = (
            b.compute(&up, &mut k0).unwrap(),
            b.compute(&turned, &mut k1).unwrap(),
        );
        let d2 = b.compute(&turned, &mut k1_unturned).unwrap();
        let (oriented, plain) = (
            hamming(rows(&d0)[0], rows(&d1)[0]),
            hamming(rows(&d0)[0], rows(&d2)[0]),
        );
        assert!(
            oriented < 30 && oriented < plain / 2,
            "{oriented} vs {plain}"
        );
    }

    #[test]
    fn bad_length_and_two_plane_images_are_errors() {
        let e = Brief::new(&BriefParams {
            bytes: 20,
            ..BriefParams::default()
        })
        .err()
        .unwrap();
        assert!(e.to_string().contains("`bytes`"), "{e}");
        let mut img = blobs(60, 60, 30.0, 30.0, 0.0);
        img.channels = 2;
        img.stride = 120;
        img.data = vec![0; 120 * 60];
        let mut b = Brief::new(&BriefParams::default()).unwrap();
        let e = b
            .compute(&img, &mut vec![keypoint(30.0, 30.0)])
            .unwrap_err();
        assert!(e.to_string().contains("one-plane"), "{e}");
    }
}
