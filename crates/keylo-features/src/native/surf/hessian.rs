//! SURF's fast-Hessian detector (Bay et al. 2008, sections 3.2–3.4): the determinant of the
//! box-filter Hessian on a stack of filter sizes per octave, maxima over 3×3×3 neighbours
//! above a threshold, refined by a quadratic fit in x, y and scale. Sizes, sampling steps and
//! margins are OpenCV's documented layout (`cv::xfeatures2d::SURF`): filter size
//! `(9 + 6·layer) · 2^octave`, layers `0..=n_octave_layers + 1` per octave (the first and last
//! only as neighbours), sampling step `2^octave`.

use keylo_core::Keypoint;

use super::haar::{apply, round_even, scale, BaseBox};
use crate::native::Integral;

/// Filter size of layer 0 of octave 0, and the growth per layer.
const SIZE0: i32 = 9;
const SIZE_STEP: i32 = 6;

/// The second-derivative filters on the 9×9 grid: ∂xx (three vertical lobes 1, -2, 1), ∂yy,
/// ∂xy (four quadrants ±1).
const DXX: [BaseBox; 3] = [[0, 2, 3, 7, 1], [3, 2, 6, 7, -2], [6, 2, 9, 7, 1]];
const DYY: [BaseBox; 3] = [[2, 0, 7, 3, 1], [2, 3, 7, 6, -2], [2, 6, 7, 9, 1]];
const DXY: [BaseBox; 4] = [
    [1, 1, 4, 4, 1],
    [5, 1, 8, 4, -1],
    [1, 5, 4, 8, -1],
    [5, 5, 8, 8, 1],
];
/// The relative weight of ∂xy in the determinant (0.9², the paper's correction).
const DXY_WEIGHT: f32 = 0.81;

/// One layer: the determinant and the sign of the trace (the Laplacian) on its sampling grid.
struct Layer {
    size: i32,
    step: usize,
    rows: usize,
    cols: usize,
    det: Vec<f32>,
    trace: Vec<f32>,
}

impl Layer {
    /// The layer of filter `size` sampled every `step` pixels; left at zero when the filter
    /// is larger than the image (such a layer is never read: see `find_maxima`).
    fn new(sat: &Integral, size: i32, step: usize) -> Self {
        let (h, w) = (sat.height(), sat.width());
        let (rows, cols) = (h / step, w / step);
        let mut layer = Self {
            size,
            step,
            rows,
            cols,
            det: vec![0.0; rows * cols],
            trace: vec![0.0; rows * cols],
        };
        let sz = size as usize;
        if sz > h || sz > w {
            return layer;
        }
        let stride = sat.stride();
        let (dxx, dyy, dxy) = (
            scale(&DXX, SIZE0, size, stride),
            scale(&DYY, SIZE0, size, stride),
            scale(&DXY, SIZE0, size, stride),
        );
        let samples_i = 1 + (h - sz) / step;
        let samples_j = 1 + (w - sz) / step;
        // The filter's centre, in samples from its top-left corner.
        let margin = (sz / 2) / step;
        let table = sat.table();
        for i in 0..samples_i {
            let row = (i + margin) * cols + margin;
            for j in 0..samples_j {
                let origin = i * step * stride + j * step;
                let dx = apply(table, origin, &dxx);
                let dy = apply(table, origin, &dyy);
                let dxy_ = apply(table, origin, &dxy);
                layer.det[row + j] = dx * dy - DXY_WEIGHT * dxy_ * dxy_;
                layer.trace[row + j] = dx + dy;
            }
        }
        layer
    }

    #[inline]
    fn at(&self, i: usize, j: usize) -> f32 {
        self.det[i * self.cols + j]
    }

    /// The 3×3 neighbourhood of sample (i, j), row by row.
    fn around(&self, i: usize, j: usize) -> [f32; 9] {
        let mut n = [0.0; 9];
        for (k, v) in n.iter_mut().enumerate() {
            *v = self.at(i + k / 3 - 1, j + k % 3 - 1);
        }
        n
    }
}

/// The keypoints of `sat`'s image: `n_octaves × n_octave_layers` scales, determinant above
/// `threshold`, in OpenCV's order (response, size, octave, y descending, then x ascending).
pub(crate) fn detect(
    sat: &Integral,
    n_octaves: usize,
    n_octave_layers: usize,
    threshold: f32,
) -> Vec<Keypoint> {
    let mut keypoints = Vec::new();
    for octave in 0..n_octaves {
        let step = 1usize << octave;
        let layers: Vec<Layer> = (0..n_octave_layers + 2)
            .map(|l| Layer::new(sat, (SIZE0 + SIZE_STEP * l as i32) << octave, step))
            .collect();
        for middle in 1..=n_octave_layers {
            find_maxima(&layers, middle, octave as i32, threshold, &mut keypoints);
        }
    }
    keypoints.sort_by(order);
    keypoints
}

/// OpenCV's keypoint order: larger response first, then larger size, higher octave, larger
/// y (row), smaller x (column).
fn order(a: &Keypoint, b: &Keypoint) -> std::cmp::Ordering {
    b.response
        .total_cmp(&a.response)
        .then(b.size.total_cmp(&a.size))
        .then(b.octave.cmp(&a.octave))
        .then(b.y.total_cmp(&a.y))
        .then(a.x.total_cmp(&b.x))
}

/// Maxima of layer `m` (with layers `m - 1` and `m + 1` as neighbours) above `threshold`.
fn find_maxima(layers: &[Layer], m: usize, octave: i32, threshold: f32, out: &mut Vec<Keypoint>) {
    let (below, here, above) = (&layers[m - 1], &layers[m], &layers[m + 1]);
    let step = here.step;
    // Samples with a whole 3×3×3 neighbourhood inside the layer above. A layer whose filter
    // is larger than the image makes this range empty for the layer below it.
    let margin = (above.size as usize / 2) / step + 1;
    let size = here.size;
    for i in margin..here.rows.saturating_sub(margin) {
        for j in margin..here.cols.saturating_sub(margin) {
            let v = here.at(i, j);
            if v <= threshold {
                continue;
            }
            let n = [below.around(i, j), here.around(i, j), above.around(i, j)];
            let is_max = n
                .iter()
                .flatten()
                .enumerate()
                .all(|(k, &x)| k == 13 || v > x);
            if !is_max {
                continue;
            }
            // The filter's top-left corner in the image, then its centre.
            let half = (size as usize / 2) / step;
            let (top, left) = (step * (i - half), step * (j - half));
            let centre = |c: usize| c as f32 + (size - 1) as f32 * 0.5;
            let trace = here.trace[i * here.cols + j];
            let mut k = Keypoint {
                x: centre(left),
                y: centre(top),
                size: size as f32,
                angle: -1.0,
                response: v,
                octave,
                class_id: i32::from(trace > 0.0) - i32::from(trace < 0.0),
            };
            if refine(&n, step as f32, (size - below.size) as f32, &mut k) {
                out.push(k);
            }
        }
    }
}

/// Fits a quadratic to the 3×3×3 neighbourhood `n` (layers below, here, above; each row by
/// row) and moves `k` to its peak; `false` when the peak is more than one sample away (or the
/// fit is degenerate).
fn refine(n: &[[f32; 9]; 3], step: f32, size_step: f32, k: &mut Keypoint) -> bool {
    let (b0, h, a0) = (&n[0], &n[1], &n[2]);
    // Negative gradient in x, y, scale.
    let g = [
        -(h[5] - h[3]) / 2.0,
        -(h[7] - h[1]) / 2.0,
        -(a0[4] - b0[4]) / 2.0,
    ];
    let dxx = h[3] - 2.0 * h[4] + h[5];
    let dxy = (h[8] - h[6] - h[2] + h[0]) / 4.0;
    let dxs = (a0[5] - a0[3] - b0[5] + b0[3]) / 4.0;
    let dyy = h[1] - 2.0 * h[4] + h[7];
    let dys = (a0[7] - a0[1] - b0[7] + b0[1]) / 4.0;
    let dss = b0[4] - 2.0 * h[4] + a0[4];
    let a = [[dxx, dxy, dxs], [dxy, dyy, dys], [dxs, dys, dss]];
    let x = solve3(&a, &g).unwrap_or([0.0; 3]);
    let ok = x.iter().any(|v| *v != 0.0) && x.iter().all(|v| v.abs() <= 1.0);
    if ok {
        k.x += x[0] * step;
        k.y += x[1] * step;
        k.size = round_even(k.size + x[2] * size_step) as f32;
    }
    ok
}

/// `a · x = b` by Cramer's rule in single precision (OpenCV's 3×3 solve); `None` when `a` is
/// singular.
fn solve3(a: &[[f32; 3]; 3], b: &[f32; 3]) -> Option<[f32; 3]> {
    let det = a[0][0] * (a[1][1] * a[2][2] - a[2][1] * a[1][2])
        - a[0][1] * (a[1][0] * a[2][2] - a[2][0] * a[1][2])
        + a[0][2] * (a[1][0] * a[2][1] - a[2][0] * a[1][1]);
    if det == 0.0 {
        return None;
    }
    let d = 1.0 / det;
    Some([
        d * (b[0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (b[1] * a[2][2] - a[1][2] * b[2])
            + a[0][2] * (b[1] * a[2][1] - a[1][1] * b[2])),
        d * (a[0][0] * (b[1] * a[2][2] - a[1][2] * b[2])
            - b[0] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * b[2] - b[1] * a[2][0])),
        d * (a[0][0] * (a[1][1] * b[2] - b[1] * a[2][1])
            - a[0][1] * (a[1][0] * b[2] - b[1] * a[2][0])
            + b[0] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])),
    ])
}
