//! The exact index math from a keypoint's K×K window in a resized image to the pixels of the
//! frame grid the window covers.
//!
//! Conventions: keypoints are in OpenCV pixel coordinates (pixel `i`'s centre is at `i`, its
//! footprint `[i - 0.5, i + 0.5)`). A resize from `grid` to `image` pixels along an axis maps
//! image pixel `i` onto grid edge coordinates `[i·grid/image, (i+1)·grid/image)`, so it covers
//! grid pixels `floor(i·grid/image) ..= ceil((i+1)·grid/image) − 1` — computed here in
//! integers, so a 2048→1024 halving covers exactly pixels `2i` and `2i+1`. Columns wrap in
//! azimuth (a window over the seam continues on the other side); rows are clipped.
//!
//! The keypoint-neighbourhood downsampler selects windows with it; the pipeline maps each
//! keypoint to the point under it ([`crate::keypoints3d`]) with the same rules.

/// The `k` consecutive pixel indices (first, last) whose centres are nearest to `centre`:
/// for odd `k` centred on the nearest pixel, for even `k` on the nearest pixel edge.
pub fn window(centre: f32, k: usize) -> (i64, i64) {
    let k = k.max(1) as i64;
    let first = (f64::from(centre) - k as f64 / 2.0 + 1.0).floor() as i64;
    (first, first + k - 1)
}

/// Grid pixels (first, last) covered by image pixels `first..=last` along one axis of
/// `image` pixels resized from `grid` pixels. Indices may lie outside `0..grid`.
pub fn cover(first: i64, last: i64, grid: usize, image: usize) -> (i64, i64) {
    let (g, n) = (grid as i64, image.max(1) as i64);
    let lo = (first * g).div_euclid(n);
    let hi = ((last + 1) * g + n - 1).div_euclid(n) - 1;
    (lo, hi)
}

/// The single grid pixel the paper's published code takes for image pixel `i`: the first
/// pixel it covers (`2i` for a halved image).
pub fn stride_pixel(i: i64, grid: usize, image: usize) -> i64 {
    (i * grid as i64).div_euclid(image.max(1) as i64)
}

/// Grid column `c` wrapped into `0..cols`.
pub fn wrap_col(c: i64, cols: usize) -> usize {
    c.rem_euclid(cols.max(1) as i64) as usize
}

/// Grid row range clipped to `0..rows`, or `None` when it lies outside.
pub fn clip_rows(first: i64, last: i64, rows: usize) -> Option<(usize, usize)> {
    let lo = first.max(0);
    let hi = last.min(rows as i64 - 1);
    (lo <= hi).then_some((lo as usize, hi as usize))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn windows_are_centred() {
        assert_eq!(window(10.0, 5), (8, 12));
        assert_eq!(window(10.4, 5), (8, 12));
        assert_eq!(window(10.6, 5), (9, 13));
        assert_eq!(window(10.0, 4), (9, 12));
        assert_eq!(window(10.6, 4), (9, 12));
        assert_eq!(window(11.2, 4), (10, 13));
        assert_eq!(window(0.0, 7), (-3, 3));
        assert_eq!(window(3.2, 1), (3, 3));
    }

    #[test]
    fn halving_covers_two_pixels_each() {
        assert_eq!(cover(0, 0, 2048, 1024), (0, 1));
        assert_eq!(cover(5, 7, 2048, 1024), (10, 15));
        assert_eq!(cover(-2, -1, 2048, 1024), (-4, -1));
        assert_eq!(cover(3, 3, 128, 64), (6, 7));
        // Same size: identity.
        assert_eq!(cover(4, 9, 1024, 1024), (4, 9));
        // Upsampled image: each grid pixel spans two image pixels.
        assert_eq!(cover(2, 2, 512, 1024), (1, 1));
        assert_eq!(cover(3, 3, 512, 1024), (1, 1));
        // Non-integer factor: pixel 1 of a 3→2 resize covers grid [1.5, 3) → pixels 1, 2.
        assert_eq!(cover(1, 1, 3, 2), (1, 2));
        assert_eq!(stride_pixel(7, 2048, 1024), 14);
    }

    #[test]
    fn wraps_and_clips() {
        assert_eq!(wrap_col(-1, 1024), 1023);
        assert_eq!(wrap_col(1025, 1024), 1);
        assert_eq!(clip_rows(-3, 2, 128), Some((0, 2)));
        assert_eq!(clip_rows(126, 130, 128), Some((126, 127)));
        assert_eq!(clip_rows(128, 130, 128), None);
    }

    proptest! {
        /// Image pixels 0..image cover the grid exactly once: consecutive spans touch and
        /// the union is 0..grid (no pixel lost or doubled by the mapping).
        #[test]
        fn spans_tile_the_grid(grid in 1usize..3000, image in 1usize..3000) {
            let mut max_hi = -1i64;
            for i in 0..image as i64 {
                let (lo, hi) = cover(i, i, grid, image);
                // Adjacent spans overlap in at most one pixel (a grid pixel split by an edge).
                prop_assert!(lo >= max_hi, "span {lo}..={hi} starts before {max_hi}");
                prop_assert!(lo <= max_hi + 1, "gap before {lo}");
                max_hi = max_hi.max(hi);
            }
            prop_assert_eq!(cover(0, 0, grid, image).0, 0);
            prop_assert_eq!(max_hi, grid as i64 - 1);
        }

        /// A window of k image pixels covers about k·grid/image grid pixels, never fewer
        /// than floor of that and at most two more.
        #[test]
        fn window_cover_size(centre in -50.0f32..2100.0, k in 1usize..12,
                             grid in 64usize..4096, image in 32usize..2048) {
            let (a, b) = window(centre, k);
            prop_assert_eq!(b - a + 1, k as i64);
            let (lo, hi) = cover(a, b, grid, image);
            let exact = k as f64 * grid as f64 / image as f64;
            let n = (hi - lo + 1) as f64;
            prop_assert!(n >= exact.floor() && n <= exact.ceil() + 1.0, "{n} vs {exact}");
        }

        /// The stride pixel is always inside the pixel's cover.
        #[test]
        fn stride_pixel_is_covered(i in -100i64..5000, grid in 1usize..4096, image in 1usize..4096) {
            let (lo, hi) = cover(i, i, grid, image);
            let s = stride_pixel(i, grid, image);
            prop_assert!(lo <= s && s <= hi.max(lo));
        }
    }
}
