//! Integral image (summed-area table) of one 8-bit plane: box sums in constant time, for
//! BRIEF's 9×9 smoothing and FREAK's receptive fields.

use keylo_core::Image;

/// Summed-area table: `at(x, y)` is the sum of the pixels left of column `x` and above row
/// `y` (so it has `(width + 1) × (height + 1)` entries, the first row and column zero).
/// Entries wrap modulo 2³² (images over 16 M pixels); box sums, differences of entries, stay
/// exact while a box's own sum fits 32 bits.
///
/// ```
/// use keylo_core::{Channel, Image};
/// use keylo_features::native::Integral;
/// let mut img = Image::new_gray(4, 3, Channel::Signal);
/// img.data.iter_mut().for_each(|p| *p = 2);
/// let sat = Integral::new(&img);
/// assert_eq!(sat.rect_sum(1, 1, 3, 3), 8); // 2×2 pixels of value 2
/// ```
#[derive(Debug, Clone)]
pub struct Integral {
    width: usize,
    height: usize,
    sums: Vec<u32>,
}

impl Integral {
    /// The table of plane 0 of `image`.
    pub fn new(image: &Image) -> Self {
        let (w, h) = (image.width, image.height);
        let stride = w + 1;
        let mut sums = vec![0u32; stride * (h + 1)];
        let rows = image.data.chunks(image.stride.max(1)).take(h);
        for (y, pixels) in rows.enumerate() {
            let (above, below) = sums.split_at_mut((y + 1) * stride);
            let (above, below) = (&above[y * stride + 1..], &mut below[1..stride]);
            if image.channels == 1 {
                accumulate(above, below, pixels.iter().take(w));
            } else {
                accumulate(above, below, pixels.iter().step_by(image.channels).take(w));
            }
        }
        Self {
            width: w,
            height: h,
            sums,
        }
    }

    /// Image width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Entries between consecutive rows of [`Integral::table`] (`width + 1`).
    pub fn stride(&self) -> usize {
        self.width + 1
    }

    /// The table, row-major: entry `(x, y)` at `y * stride() + x`.
    pub fn table(&self) -> &[u32] {
        &self.sums
    }

    #[inline]
    fn at(&self, x: usize, y: usize) -> u32 {
        self.sums[y * (self.width + 1) + x]
    }

    /// Sum of the pixels in columns `x0..x1` and rows `y0..y1` (clamped to the image).
    #[inline]
    pub fn rect_sum(&self, x0: usize, y0: usize, x1: usize, y1: usize) -> u32 {
        let (x1, y1) = (x1.min(self.width), y1.min(self.height));
        let (x0, y0) = (x0.min(x1), y0.min(y1));
        (self.at(x1, y1).wrapping_add(self.at(x0, y0)))
            .wrapping_sub(self.at(x1, y0).wrapping_add(self.at(x0, y1)))
    }

    /// Sum of the `(2 half + 1)²` box centred on pixel `(x, y)`; the caller keeps the box
    /// inside the image (parts outside are clamped away).
    #[inline]
    pub fn box_sum(&self, x: usize, y: usize, half: usize) -> u32 {
        self.rect_sum(
            x.saturating_sub(half),
            y.saturating_sub(half),
            x + half + 1,
            y + half + 1,
        )
    }

    /// Sums of the `(2 half + 1)²` box centred on every pixel (clipped to the image), row-major
    /// with the image's width as stride: BRIEF's smoothed image. `half` ≤ 7 (so a sum of
    /// 8-bit pixels fits 16 bits).
    pub fn box_sums(&self, half: usize) -> Vec<u16> {
        let half = half.min(7);
        let (w, h) = (self.width, self.height);
        let mut out = vec![0u16; w * h];
        let stride = w + 1;
        let k = 2 * half + 1;
        for y in 0..h {
            let row = &mut out[y * w..(y + 1) * w];
            if y < half || y + half >= h || w < k {
                for (x, v) in row.iter_mut().enumerate() {
                    *v = self.box_sum(x, y, half) as u16;
                }
                continue;
            }
            let (top, bottom) = ((y - half) * stride, (y + half + 1) * stride);
            let (t, b) = (
                &self.sums[top..top + stride],
                &self.sums[bottom..bottom + stride],
            );
            // Pixel x's box spans table columns x - half .. x + half + 1.
            let inner = &mut row[half..w - half];
            let (bl, br) = (&b[..w - 2 * half], &b[k..]);
            let (tl, tr) = (&t[..w - 2 * half], &t[k..]);
            for (i, v) in inner.iter_mut().enumerate() {
                *v = (br[i].wrapping_add(tl[i])).wrapping_sub(bl[i].wrapping_add(tr[i])) as u16;
            }
            for x in (0..half).chain(w - half..w) {
                row[x] = self.box_sum(x, y, half) as u16;
            }
        }
        out
    }

    /// Mean intensity over the whole-pixel square nearest to the square of half-width `half`
    /// centred on `(x, y)` (its edges rounded to pixel edges; at least one pixel; clipped to
    /// the image): four table entries, for fields large enough that rounding hardly matters.
    #[inline]
    pub fn rounded_box_mean(&self, x: f32, y: f32, half: f32) -> f32 {
        // `as` truncates (and saturates at 0): floor(v + ½) for v ≥ 0 without a libm call.
        let edge = |v: f32, n: usize| ((v + 0.5) as usize).min(n);
        let (cx, cy) = (x + 0.5, y + 0.5);
        let (x0, x1) = (edge(cx - half, self.width), edge(cx + half, self.width));
        let (y0, y1) = (edge(cy - half, self.height), edge(cy + half, self.height));
        let (x1, y1) = (
            x1.max(x0 + 1).min(self.width),
            y1.max(y0 + 1).min(self.height),
        );
        let area = (x1.saturating_sub(x0) * y1.saturating_sub(y0)).max(1);
        self.rect_sum(x0, y0, x1, y1) as f32 / area as f32
    }

    /// Integer part and fraction of a table coordinate, clamped to `0 ..= n` (the fraction
    /// is 1 at `n`, so `i + 1` stays inside the table).
    #[inline]
    fn split(v: f32, n: usize) -> (usize, f32) {
        let v = v.clamp(0.0, n as f32);
        // Truncation is floor for v ≥ 0, and cheaper than `f32::floor`.
        let i = (v as usize).min(n.saturating_sub(1));
        (i, v - i as f32)
    }

    /// Mean intensity over the square of half-width `half` (≥ 0.5 px) centred on the image
    /// point `(x, y)` (pixel centres at integer coordinates, as keypoints are), with fractional
    /// pixels weighted by the area covered (parts outside the image count as 0). At
    /// `half = 0.5` this is bilinear interpolation.
    ///
    /// The table is bilinear between its entries — the exact area-weighted pixel sum over
    /// `[0, x] × [0, y]` of the piecewise-constant image — and the four corners' values are
    /// combined as integer differences first, so large sums lose no precision.
    #[inline]
    pub fn area_mean(&self, x: f32, y: f32, half: f32) -> f32 {
        let half = half.max(0.5);
        let (cx, cy) = (x + 0.5, y + 0.5);
        let (x0, fx0) = Self::split(cx - half, self.width);
        let (x1, fx1) = Self::split(cx + half, self.width);
        let (y0, fy0) = Self::split(cy - half, self.height);
        let (y1, fy1) = Self::split(cy + half, self.height);
        let stride = self.width + 1;
        let d = |a: usize, b: usize| self.sums[b].wrapping_sub(self.sums[a]) as f32;
        // Sum over [x0 + fx0, x1 + fx1] of table row `r` (a difference along x).
        let across = |r: usize| {
            let row = r * stride;
            d(row + x0, row + x1) + fx1 * d(row + x1, row + x1 + 1)
                - fx0 * d(row + x0, row + x0 + 1)
        };
        let at_y = |r: usize, f: f32| {
            let lo = across(r);
            lo + f * (across(r + 1) - lo)
        };
        let sum = at_y(y1, fy1) - at_y(y0, fy0);
        sum / (4.0 * half * half)
    }
}

/// One row of the table: `below[x] = above[x] + sum of the row's first x + 1 pixels`.
#[inline]
fn accumulate<'a>(above: &[u32], below: &mut [u32], pixels: impl Iterator<Item = &'a u8>) {
    let mut run = 0u32;
    for ((b, a), &v) in below.iter_mut().zip(above).zip(pixels) {
        run = run.wrapping_add(u32::from(v));
        *b = a.wrapping_add(run);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Channel;
    use proptest::prelude::*;

    fn image(w: usize, h: usize, seed: u32) -> Image {
        let mut img = Image::new_gray(w, h, Channel::Signal);
        for (i, p) in img.data.iter_mut().enumerate() {
            *p = ((i as u32).wrapping_mul(2654435761).wrapping_add(seed) >> 24) as u8;
        }
        img
    }

    fn brute(img: &Image, x0: usize, y0: usize, x1: usize, y1: usize) -> u32 {
        let mut s = 0;
        for y in y0..y1 {
            for x in x0..x1 {
                s += u32::from(img.data[y * img.stride + x]);
            }
        }
        s
    }

    proptest! {
        #[test]
        fn rect_sums_match_brute_force(
            w in 1usize..40, h in 1usize..20, seed in 0u32..1000,
            a in 0usize..40, b in 0usize..40, c in 0usize..20, d in 0usize..20,
        ) {
            let img = image(w, h, seed);
            let sat = Integral::new(&img);
            let (x0, x1) = (a.min(b).min(w), a.max(b).min(w));
            let (y0, y1) = (c.min(d).min(h), c.max(d).min(h));
            prop_assert_eq!(sat.rect_sum(x0, y0, x1, y1), brute(&img, x0, y0, x1, y1));
        }

        #[test]
        fn area_means_of_whole_pixels_are_box_means(
            seed in 0u32..1000, x in 4usize..36, y in 4usize..16, half in 0usize..4,
        ) {
            let img = image(40, 20, seed);
            let sat = Integral::new(&img);
            let n = (2 * half + 1) as f32;
            let expected = sat.box_sum(x, y, half) as f32 / (n * n);
            let got = sat.area_mean(x as f32, y as f32, half as f32 + 0.5);
            prop_assert!((got - expected).abs() < 1e-3 * expected.max(1.0));
        }
    }

    #[test]
    fn box_sums_are_clipped_box_sums_everywhere() {
        for (w, h) in [(30, 12), (5, 3), (40, 9)] {
            let img = image(w, h, 3);
            let sat = Integral::new(&img);
            let boxes = sat.box_sums(4);
            for y in 0..h {
                for x in 0..w {
                    let (x0, y0) = (x.saturating_sub(4), y.saturating_sub(4));
                    let expected = brute(&img, x0, y0, (x + 5).min(w), (y + 5).min(h));
                    assert_eq!(
                        u32::from(boxes[y * w + x]),
                        expected,
                        "({x}, {y}) of {w}×{h}"
                    );
                }
            }
        }
    }

    #[test]
    fn rounded_boxes_are_whole_pixel_means() {
        let img = image(20, 20, 5);
        let sat = Integral::new(&img);
        // Centre (10.5, 8.5) ± 2.2 → pixel edges 8..13 × 6..11.
        let expected = brute(&img, 8, 6, 13, 11) as f32 / 25.0;
        assert!((sat.rounded_box_mean(10.0, 8.0, 2.2) - expected).abs() < 1e-4);
        // Whole-pixel squares agree with the area-weighted mean.
        let a = sat.area_mean(10.0, 8.0, 2.5);
        assert!((sat.rounded_box_mean(10.0, 8.0, 2.5) - a).abs() < 1e-3);
    }

    #[test]
    fn half_pixel_box_is_bilinear_interpolation() {
        let img = image(8, 8, 7);
        let sat = Integral::new(&img);
        let p = |x: usize, y: usize| f32::from(img.data[y * 8 + x]);
        let (fx, fy) = (0.25f32, 0.75f32);
        let expected = (p(3, 4) * (1.0 - fx) + p(4, 4) * fx) * (1.0 - fy)
            + (p(3, 5) * (1.0 - fx) + p(4, 5) * fx) * fy;
        let got = sat.area_mean(3.0 + fx, 4.0 + fy, 0.5);
        assert!((got - expected).abs() < 1e-3, "{got} vs {expected}");
    }
}
