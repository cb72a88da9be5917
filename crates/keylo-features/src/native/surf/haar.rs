//! Box filters on an integral image, SURF's approximation of Gaussian derivatives (Bay et al.
//! 2008, section 3.2): each filter is a few weighted boxes, defined on a base grid and scaled
//! to the filter's size with its corners rounded to whole pixels.

/// A box as `[x0, y0, x1, y1, weight]` on the base grid (corners inclusive-exclusive).
pub(crate) type BaseBox = [i32; 5];

/// One scaled box: the offsets of its four corners in the integral table and its weight
/// divided by its area (so a filter answers in mean-intensity units).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScaledBox {
    top_left: usize,
    bottom_left: usize,
    top_right: usize,
    bottom_right: usize,
    weight: f32,
}

/// Round half to even, as OpenCV's `cvRound` of a float (the SSE conversion). Below 2²²
/// in magnitude, adding and subtracting 1.5·2²³ rounds in the FPU's own nearest-even mode
/// (no library call, the hot path of the descriptor window).
#[inline]
pub(crate) fn round_even(v: f32) -> i32 {
    const MAGIC: f32 = 12_582_912.0;
    if v.abs() < 4_194_304.0 {
        ((v + MAGIC) - MAGIC) as i32
    } else {
        v.round_ties_even() as i32
    }
}

/// `boxes` (defined on a `base × base` grid) scaled to `size`, for an integral table whose
/// rows are `stride` entries apart.
pub(crate) fn scale<const N: usize>(
    boxes: &[BaseBox; N],
    base: i32,
    size: i32,
    stride: usize,
) -> [ScaledBox; N] {
    let ratio = size as f32 / base as f32;
    boxes.map(|[x0, y0, x1, y1, w]| {
        let (x0, y0) = (round_even(ratio * x0 as f32), round_even(ratio * y0 as f32));
        let (x1, y1) = (round_even(ratio * x1 as f32), round_even(ratio * y1 as f32));
        let at = |x: i32, y: i32| y.max(0) as usize * stride + x.max(0) as usize;
        ScaledBox {
            top_left: at(x0, y0),
            bottom_left: at(x0, y1),
            top_right: at(x1, y0),
            bottom_right: at(x1, y1),
            weight: w as f32 / ((x1 - x0) as f32 * (y1 - y0) as f32),
        }
    })
}

/// The filter's answer with its top-left corner at `origin` of the integral `table`: each
/// box's sum times its weight in single precision, added up in double, as OpenCV does.
#[inline]
pub(crate) fn apply(table: &[u32], origin: usize, boxes: &[ScaledBox]) -> f32 {
    let mut d = 0.0f64;
    for b in boxes {
        // The table wraps modulo 2³² on very large images; a box's own sum never does.
        let sum = table[origin + b.top_left]
            .wrapping_add(table[origin + b.bottom_right])
            .wrapping_sub(table[origin + b.bottom_left])
            .wrapping_sub(table[origin + b.top_right]);
        d += f64::from(sum as f32 * b.weight);
    }
    d as f32
}

#[cfg(test)]
mod tests {
    use super::round_even;

    #[test]
    fn rounds_half_to_even_as_opencv() {
        for (v, want) in [
            (0.5f32, 0),
            (1.5, 2),
            (2.5, 2),
            (-0.5, 0),
            (-1.5, -2),
            (-2.5, -2),
            (2.4999998, 2),
            (2.5000002, 3),
            (1e7, 10_000_000),
            (-3.7, -4),
        ] {
            assert_eq!(round_even(v), want, "{v}");
            assert_eq!(round_even(v), v.round_ties_even() as i32, "{v}");
        }
    }
}
