//! Integral image (summed-area table) of one 8-bit plane: box sums in constant time, for
//! BRIEF's 9×9 smoothing and FREAK's receptive fields.

use keylo_core::Image;

/// Summed-area table: `at(x, y)` is the sum of the pixels left of column `x` and above row
/// `y` (so it has `(width + 1) × (height + 1)` entries, the first row and column zero).
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
    /// The table of plane 0 of `image` (8-bit: a 1024×64 image sums to at most 2^24).
    pub fn new(image: &Image) -> Self {
        let (w, h) = (image.width, image.height);
        let stride = w + 1;
        let mut sums = vec![0u32; stride * (h + 1)];
        for y in 0..h {
            let mut row = 0u32;
            let start = y * image.stride;
            for x in 0..w {
                let v = image.data.get(start + x * image.channels).copied();
                row += u32::from(v.unwrap_or(0));
                sums[(y + 1) * stride + x + 1] = sums[y * stride + x + 1] + row;
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

    #[inline]
    fn at(&self, x: usize, y: usize) -> u32 {
        self.sums[y * (self.width + 1) + x]
    }

    /// Sum of the pixels in columns `x0..x1` and rows `y0..y1` (clamped to the image).
    #[inline]
    pub fn rect_sum(&self, x0: usize, y0: usize, x1: usize, y1: usize) -> u32 {
        let (x1, y1) = (x1.min(self.width), y1.min(self.height));
        let (x0, y0) = (x0.min(x1), y0.min(y1));
        self.at(x1, y1) + self.at(x0, y0) - self.at(x1, y0) - self.at(x0, y1)
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

    /// The table at a real position (bilinear between entries), clamped to the image: the
    /// exact area-weighted pixel sum over `[0, x] × [0, y]` of the piecewise-constant image.
    #[inline]
    fn at_real(&self, x: f32, y: f32) -> f32 {
        let x = x.clamp(0.0, self.width as f32);
        let y = y.clamp(0.0, self.height as f32);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.width), (y0 + 1).min(self.height));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let top = self.at(x0, y0) as f32 * (1.0 - fx) + self.at(x1, y0) as f32 * fx;
        let bottom = self.at(x0, y1) as f32 * (1.0 - fx) + self.at(x1, y1) as f32 * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// Mean intensity over the square of half-width `half` (≥ 0.5 px) centred on the image
    /// point `(x, y)` (pixel centres at integer coordinates, as keypoints are), with fractional
    /// pixels weighted by the area covered. At `half = 0.5` this is bilinear interpolation.
    #[inline]
    pub fn area_mean(&self, x: f32, y: f32, half: f32) -> f32 {
        let half = half.max(0.5);
        let (cx, cy) = (x + 0.5, y + 0.5);
        let (x0, x1, y0, y1) = (cx - half, cx + half, cy - half, cy + half);
        let sum = self.at_real(x1, y1) + self.at_real(x0, y0)
            - self.at_real(x1, y0)
            - self.at_real(x0, y1);
        sum / (4.0 * half * half)
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
