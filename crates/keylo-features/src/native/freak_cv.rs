//! FREAK as OpenCV contrib computes it (`freak` with `pattern = "opencv"`): the paper's retina
//! pattern quantised to 64 scales × 256 orientations, each receptive field averaged over a
//! square of the integral image with its edges rounded half to even (bilinear interpolation when its half-width is below
//! half a pixel), all in integers; the orientation from 45 pairs with integer weights; the
//! 512 tests of [`super::freak_opencv`]. OpenCV's descriptors bit for bit
//! (`tests/brief_freak_opencv.rs`); its angles within 1e-4° (`scripts/peers/freak_pattern.py`
//! checks the model against OpenCV's). The orientation weights round half up (`floor(v +
//! 0.5)`), which is what OpenCV 4.14's angles need, negative weights included.

use std::f64::consts::PI;

use keylo_core::Keypoint;

use super::freak_opencv::{ORIENTATION_PAIRS, PAIRS};
use super::input::Plane;
use super::Integral;

const SCALES: usize = 64;
const ORIENTATIONS: usize = 256;
const FIELDS: usize = 43;
const SMALLEST_KEYPOINT_SIZE: f32 = 7.0;
/// ln 2 as OpenCV writes it (15 digits, not `LN_2`), and ln 3 (the scale of every keypoint
/// without scale normalisation: as if its size were 3 × 7 px).
#[allow(clippy::approx_constant)]
const LN2: f64 = 0.693147180559945;
const LN3: f64 = 1.0986122886681;

/// Ring radii and field sizes of the pattern, outer ring first, in pattern units.
fn rings() -> ([f64; 8], [f64; 8]) {
    let (big, small) = (2.0 / 3.0, 2.0 / 24.0);
    let unit = (big - small) / 21.0;
    let r = [
        big,
        big - 6.0 * unit,
        big - 11.0 * unit,
        big - 15.0 * unit,
        big - 18.0 * unit,
        big - 20.0 * unit,
        small,
        0.0,
    ];
    let s = [
        r[0] / 2.0,
        r[1] / 2.0,
        r[2] / 2.0,
        r[3] / 2.0,
        r[4] / 2.0,
        r[5] / 2.0,
        r[6] / 2.0,
        r[6] / 2.0,
    ];
    (r, s)
}

/// OpenCV's FREAK sampling for one `pattern_scale` and octave count.
pub(crate) struct CvFreak {
    pattern_scale: f64,
    /// `2^(n_octaves · s / 64)` per scale index `s`.
    factors: [f64; SCALES],
    radius: [f64; 8],
    sigma: [f64; 8],
    /// Half-size of the pattern per scale, pixels (keypoints closer to a border are dropped).
    sizes: [i32; SCALES],
    /// Integer weights of the orientation pairs.
    weights: [(i32, i32); 45],
    size_cst: f32,
    scale_normalized: bool,
    orientation_normalized: bool,
}

impl CvFreak {
    pub fn new(
        pattern_scale: f32,
        n_octaves: i32,
        scale_normalized: bool,
        orientation_normalized: bool,
    ) -> Self {
        let (radius, sigma) = rings();
        let scale_step = 2f64.powf(f64::from(n_octaves) / SCALES as f64);
        let mut f = Self {
            pattern_scale: f64::from(pattern_scale),
            factors: std::array::from_fn(|s| scale_step.powf(s as f64)),
            radius,
            sigma,
            sizes: [0; SCALES],
            weights: [(0, 0); 45],
            size_cst: (SCALES as f64 / (LN2 * f64::from(n_octaves))) as f32,
            scale_normalized,
            orientation_normalized,
        };
        for s in 0..SCALES {
            let factor = f.factors[s];
            f.sizes[s] = (0..8)
                .map(|i| ((radius[i] + sigma[i]) * factor * f.pattern_scale).ceil() as i32 + 1)
                .max()
                .unwrap_or(0);
        }
        f.weights = ORIENTATION_PAIRS.map(|[i, j]| {
            let (a, b) = (f.point(0, 0, usize::from(i)), f.point(0, 0, usize::from(j)));
            let (dx, dy) = (a.0 - b.0, a.1 - b.1);
            let n2 = dx * dx + dy * dy;
            let weight = |d: f32| (f64::from(d / n2) * 4096.0 + 0.5).floor() as i32;
            (weight(dx), weight(dy))
        });
        f
    }

    /// Field `p` at `scale` and orientation step `o`: offset and half-width, pixels.
    fn point(&self, scale: usize, o: usize, p: usize) -> (f32, f32, f32) {
        let (ring, k, n) = if p < 42 {
            (p / 6, p % 6, 6.0)
        } else {
            (7, 0, 1.0)
        };
        let f = self.factors[scale];
        let theta = o as f64 * 2.0 * PI / ORIENTATIONS as f64;
        let beta = PI / n * (ring % 2) as f64;
        let alpha = k as f64 * 2.0 * PI / n + beta + theta;
        let r = self.radius[ring];
        (
            (r * alpha.cos() * f * self.pattern_scale) as f32,
            (r * alpha.sin() * f * self.pattern_scale) as f32,
            (self.sigma[ring] * f * self.pattern_scale) as f32,
        )
    }

    /// The scale index of `kp`, or `None` when its pattern leaves the `w × h` image.
    fn scale_of(&self, kp: &Keypoint, w: usize, h: usize) -> Option<usize> {
        let raw = if self.scale_normalized {
            f64::from((kp.size / SMALLEST_KEYPOINT_SIZE).ln() * self.size_cst) + 0.5
        } else {
            LN3 * f64::from(self.size_cst) + 0.5
        };
        let s = (raw as i32).clamp(0, SCALES as i32 - 1) as usize;
        let m = self.sizes[s] as f32;
        let inside = kp.x > m && kp.y > m && kp.x < w as f32 - m && kp.y < h as f32 - m;
        inside.then_some(s)
    }

    /// Field `p`'s mean intensity, rounded, for a keypoint at `(x, y)`.
    fn mean(
        &self,
        img: &Plane,
        sat: &Integral,
        (x, y): (f32, f32),
        s: usize,
        o: usize,
        p: usize,
    ) -> i32 {
        let (px, py, r) = self.point(s, o, p);
        let (xf, yf) = (px + x, py + y);
        let (ix, iy) = (xf as i32 as usize, yf as i32 as usize);
        if r < 0.5 {
            let rx = ((xf - ix as f32) * 1024.0) as i64;
            let ry = ((yf - iy as f32) * 1024.0) as i64;
            let v = |dx: usize, dy: usize| i64::from(img.at(ix + dx, iy + dy));
            let sum = (1024 - rx) * (1024 - ry) * v(0, 0)
                + rx * (1024 - ry) * v(1, 0)
                + (1024 - rx) * ry * v(0, 1)
                + rx * ry * v(1, 1);
            return ((sum + 2 * 1024 * 1024) / (4 * 1024 * 1024)) as i32;
        }
        // The square's edges rounded half to even; the integral table is one larger.
        let edge = |v: f32| v.round_ties_even() as i32 as usize;
        let (left, top) = (edge(xf - r), edge(yf - r));
        let (right, bottom) = (edge(xf + r + 1.0), edge(yf + r + 1.0));
        let (t, stride) = (sat.table(), sat.stride());
        let at = |x: usize, y: usize| t[y * stride + x];
        // The table wraps modulo 2³² on very large images; a square's own sum never does.
        let sum = at(right, bottom)
            .wrapping_sub(at(left, bottom))
            .wrapping_add(at(left, top))
            .wrapping_sub(at(right, top));
        let sum = i64::from(sum);
        let area = ((right - left) * (bottom - top)) as i64;
        ((sum + area / 2) / area) as i32
    }

    /// The descriptor of `kp` (64 bytes) appended to `out`, its angle set as OpenCV sets it;
    /// `false` (nothing appended) when its pattern leaves the image.
    pub fn describe(
        &self,
        img: &Plane,
        sat: &Integral,
        kp: &mut Keypoint,
        out: &mut Vec<u8>,
    ) -> bool {
        let Some(s) = self.scale_of(kp, img.width, img.height) else {
            return false;
        };
        let at = (kp.x, kp.y);
        let mut v = [0i32; FIELDS];
        let theta = if self.orientation_normalized {
            for (p, value) in v.iter_mut().enumerate() {
                *value = self.mean(img, sat, at, s, 0, p);
            }
            let (mut d0, mut d1) = (0i32, 0i32);
            for (&[i, j], &(wx, wy)) in ORIENTATION_PAIRS.iter().zip(&self.weights) {
                let delta = v[usize::from(i)] - v[usize::from(j)];
                d0 += delta * wx / 2048;
                d1 += delta * wy / 2048;
            }
            kp.angle = (f64::from((d1 as f32).atan2(d0 as f32)) * (180.0 / PI)) as f32;
            let t = f64::from(ORIENTATIONS as f32 * kp.angle) * (1.0 / 360.0);
            let t = if kp.angle < 0.0 { t - 0.5 } else { t + 0.5 } as i32;
            t.rem_euclid(ORIENTATIONS as i32) as usize
        } else {
            kp.angle = 0.0;
            0
        };
        for (p, value) in v.iter_mut().enumerate() {
            *value = self.mean(img, sat, at, s, theta, p);
        }
        out.extend(PAIRS.chunks_exact(8).map(|eight| {
            eight.iter().fold(0u8, |byte, &[i, j]| {
                (byte << 1) | u8::from(v[usize::from(i)] >= v[usize::from(j)])
            })
        }));
        true
    }
}
