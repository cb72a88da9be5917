//! The 8-bit signal images of Ouster's ROS driver (`ouster-ros`, its image node), which the
//! paper's authors recorded: the driver's auto exposure maps the frame's 10th and 90th
//! percentiles of the non-zero values to 0.1 and 0.9, the result is clipped to 0–1, its
//! square root is written as a 16-bit image (`sqrt(x) · 65535`), and the authors' subscriber
//! kept its top byte (`uint8(mono16 / 256)`).
//!
//! The square root makes weak returns bright: one count of a sensor whose 90th percentile is
//! 200 counts reads grey 17, two read 24, three 29. Real images made this way show exactly
//! these steps in their dark regions (docs/results/sim-realism.md).

/// Share of the non-zero values below the low and above the high exposure point.
const PERCENTILE: f64 = 0.1;
/// The driver looks at every 4th pixel.
const STRIDE: usize = 4;
/// With fewer non-zero pixels sampled the driver has no exposure yet.
const MIN_SAMPLES: usize = 100;

/// The driver's exposure: the affine map of values to 0–1 before the square root.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Exposure {
    scale: f64,
    offset: f64,
}

impl Exposure {
    /// The exposure of one frame from its own percentiles (the driver's first frame; later it
    /// smooths `lo` and `hi` over frames, which for a still or slowly moving sensor settles
    /// on the same values).
    fn of(values: &[f32], valid: &[bool]) -> Option<Self> {
        let mut v: Vec<f64> = values
            .iter()
            .zip(valid)
            .step_by(STRIDE)
            .filter(|(x, ok)| **ok && x.is_finite() && **x > 0.0)
            .map(|(x, _)| f64::from(*x))
            .collect();
        if v.len() < MIN_SAMPLES {
            return None;
        }
        let k = (v.len() as f64 * PERCENTILE) as usize;
        let top = v.len() - k - 1;
        let (_, &mut hi, _) = v.select_nth_unstable_by(top, f64::total_cmp);
        let (_, &mut lo, _) = v[..=top].select_nth_unstable_by(k, f64::total_cmp);
        let span_scale = (1.0 - 2.0 * PERCENTILE) / (hi - lo);
        Some(if !span_scale.is_finite() {
            // No spread: the driver maps everything relative to hi = 0.5.
            Self {
                scale: 0.5 / hi,
                offset: 0.0,
            }
        } else if PERCENTILE - span_scale * lo <= 0.0 {
            Self {
                scale: span_scale,
                offset: PERCENTILE - span_scale * lo,
            }
        } else {
            // The affine map would lift 0 above 0: scale by hi alone.
            Self {
                scale: (1.0 - PERCENTILE) / hi,
                offset: 0.0,
            }
        })
    }

    /// The 8-bit grey of `value`.
    fn grey(self, value: f32) -> u8 {
        let x = (f64::from(value) * self.scale + self.offset).clamp(0.0, 1.0);
        let mono16 = (x.sqrt() * 65535.0) as u32;
        (mono16 / 256) as u8
    }
}

/// Writes the driver's 8-bit image of `values` into `out`; invalid pixels stay 0. A frame
/// with fewer than 100 non-zero pixels among every 4th stays black.
pub(super) fn driver_image(values: &[f32], valid: &[bool], out: &mut [u8]) {
    let Some(exposure) = Exposure::of(values, valid) else {
        return;
    };
    for ((o, &v), &ok) in out.iter_mut().zip(values).zip(valid) {
        if ok && v.is_finite() {
            *o = exposure.grey(v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1000 pixels: values 1..=1000 (the 10th percentile of every 4th is 41, the 90th 961).
    fn ramp() -> (Vec<f32>, Vec<bool>) {
        ((1..=1000).map(|i| i as f32).collect(), vec![true; 1000])
    }

    #[test]
    fn exposure_follows_the_drivers_percentiles() {
        let (v, ok) = ramp();
        let e = Exposure::of(&v, &ok).unwrap();
        // Sampled: 1, 5, …, 997 (250 values); k = 25: lo = 101, hi = 897.
        let (lo, hi) = (101.0, 897.0);
        assert!((e.scale - 0.8 / (hi - lo)).abs() < 1e-12);
        assert!((e.offset - (0.1 - e.scale * lo)).abs() < 1e-12);
    }

    #[test]
    fn weak_returns_read_in_square_root_steps() {
        // Half the pixels dark (1–3 counts), half 20–219: lo is below hi / 9, so the map
        // scales by hi alone (x = 0.9 v / hi).
        let mut v: Vec<f32> = (0..4000)
            .map(|i| {
                if i % 8 < 4 {
                    (1 + i % 3) as f32
                } else {
                    (20 + i % 200) as f32
                }
            })
            .collect();
        v[0] = 0.0;
        let ok = vec![true; v.len()];
        let mut out = vec![0u8; v.len()];
        driver_image(&v, &ok, &mut out);
        let e = Exposure::of(&v, &ok).unwrap();
        assert_eq!(e.offset, 0.0);
        let step = |counts: f32| e.grey(counts);
        let g1 = f64::from(step(1.0));
        // Two counts read √2 times one count's grey, four counts twice it (within rounding).
        assert!(
            (f64::from(step(2.0)) / g1 - 2f64.sqrt()).abs() < 0.06,
            "{g1}"
        );
        assert!((f64::from(step(4.0)) / g1 - 2.0).abs() < 0.06, "{g1}");
        assert_eq!(out[0], 0);
        assert_eq!(*out.iter().max().unwrap(), 255);
    }

    #[test]
    fn invalid_and_sparse_frames_stay_black() {
        let (v, mut ok) = ramp();
        ok[500] = false;
        let mut out = vec![0u8; v.len()];
        driver_image(&v, &ok, &mut out);
        assert_eq!(out[500], 0);
        assert_eq!(out[999], 255);
        let mut few = vec![0u8; 300];
        driver_image(&v[..300], &ok[..300], &mut few);
        assert!(few.iter().all(|&g| g == 0), "75 samples are fewer than 100");
    }
}
