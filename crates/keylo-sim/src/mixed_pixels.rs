//! Mixed pixels: a return next to a range jump along its row reads only part of its signal
//! (the `ouster` appearance; measured on the real Ouster captures).

use crate::noise::{hash_words, unit};

/// A pixel whose left or right neighbour lies across a range jump reads a share of its
/// signal (and of the reflectivity the sensor derives from it): its beam's footprint falls
/// partly on the other surface. A jump is a range difference above `relative · r + absolute_m`;
/// the share is uniform in `low..high`, drawn per pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MixedPixels {
    /// Range jump relative to the pixel's range.
    pub relative: f64,
    /// Range jump added to the relative one, metres.
    pub absolute_m: f64,
    /// Range of the share of its signal a mixed pixel reads.
    pub low: f64,
    /// See `low`.
    pub high: f64,
}

/// Salt of the mixed pixels' hashes.
const MIXED_PIXEL_SALT: u64 = 0x313E_D9A1;

impl MixedPixels {
    /// Scales, in place, the signal and reflectivity of every valid pixel with a valid left
    /// or right neighbour across a range jump (columns wrap around: a frame is a full turn).
    /// Arrays are row-major, `rows × cols`; the draw depends on `(seed, frame, row, col)`.
    pub fn apply(
        &self,
        (seed, frame): (u64, u64),
        (rows, cols): (usize, usize),
        valid: &[bool],
        range: &[f32],
        signal: &mut [f32],
        reflectivity: &mut [f32],
    ) {
        if cols < 2 {
            return;
        }
        for r in 0..rows {
            let row = r * cols;
            for c in 0..cols {
                let i = row + c;
                if !valid[i] {
                    continue;
                }
                let own = f64::from(range[i]);
                let jump = self.relative * own + self.absolute_m;
                let across = [(c + cols - 1) % cols, (c + 1) % cols]
                    .into_iter()
                    .any(|n| valid[row + n] && (f64::from(range[row + n]) - own).abs() > jump);
                if across {
                    let h = hash_words(&[seed, MIXED_PIXEL_SALT, frame, r as u64, c as u64]);
                    let share = self.low + (self.high - self.low) * f64::from(unit(h));
                    signal[i] = (f64::from(signal[i]) * share) as f32;
                    reflectivity[i] = (f64::from(reflectivity[i]) * share) as f32;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIXED: MixedPixels = MixedPixels {
        relative: 0.3,
        absolute_m: 0.2,
        low: 0.3,
        high: 1.0,
    };

    /// One row: a wall at 5 m with a post at 2 m in columns 4..=6, one invalid pixel.
    fn row() -> (Vec<bool>, Vec<f32>) {
        let range: Vec<f32> = (0..12)
            .map(|c| {
                if (4..=6).contains(&c) {
                    2.0
                } else {
                    5.0 + 0.01 * c as f32
                }
            })
            .collect();
        let mut valid = vec![true; 12];
        valid[9] = false;
        (valid, range)
    }

    #[test]
    fn only_pixels_beside_a_jump_are_dimmed_within_the_share() {
        let (valid, range) = row();
        let (mut signal, mut refl) = (vec![1000.0f32; 12], vec![50.0f32; 12]);
        MIXED.apply((7, 3), (1, 12), &valid, &range, &mut signal, &mut refl);
        for (c, (&s, &f)) in signal.iter().zip(&refl).enumerate() {
            if [3, 4, 6, 7].contains(&c) {
                assert!((300.0..=1000.0).contains(&s), "column {c}: {s}");
                assert!(
                    (f / 50.0 - s / 1000.0).abs() < 1e-6,
                    "column {c}: same share"
                );
            } else {
                // Inside a surface, beside the invalid pixel, or the post's middle.
                assert_eq!((s, f), (1000.0, 50.0), "column {c}");
            }
        }
        assert!(
            signal.iter().any(|&s| s < 950.0),
            "some edge pixel is dimmed"
        );
    }

    #[test]
    fn the_same_pixel_is_dimmed_the_same_way_and_columns_wrap() {
        let (valid, range) = row();
        let run = |seed| {
            let mut s = vec![1000.0f32; 12];
            let mut f = vec![50.0f32; 12];
            MIXED.apply((seed, 3), (1, 12), &valid, &range, &mut s, &mut f);
            s
        };
        assert_eq!(run(7), run(7));
        assert_ne!(run(7), run(8));
        // Column 0 and the last column are neighbours.
        let range = [2.0f32, 5.0, 5.0, 5.0, 5.0, 5.0];
        let mut s = [1000.0f32; 6];
        MIXED.apply((1, 0), (1, 6), &[true; 6], &range, &mut s, &mut [1.0; 6]);
        assert!(s[5] < 1000.0 || s[1] < 1000.0 || s[0] < 1000.0);
        assert_eq!(&s[2..5], &[1000.0; 3]);
    }
}
