//! XFeat's dense outputs → keypoints and 64-d unit descriptors, as the authors'
//! `detectAndCompute` does it: the keypoint heatmap (softmax over the 65 logits, the 64 cell
//! positions unshuffled to full resolution), max-pool suppression above a threshold, each
//! keypoint scored by its heatmap value × the bilinear reliability, the best `top_k` kept,
//! descriptors sampled bicubically from the unit-normalised dense map and normalised again.
//! Positions map to the maps as PyTorch's `grid_sample` with `align_corners = False` on
//! XFeat's normalisation (`2·p/(size − 1) − 1`).

/// A map of `rows × cols` values, row-major.
pub struct Map<'a> {
    pub data: &'a [f32],
    pub rows: usize,
    pub cols: usize,
}

impl Map<'_> {
    #[inline]
    fn at(&self, x: i64, y: i64) -> f32 {
        if x < 0 || y < 0 || x >= self.cols as i64 || y >= self.rows as i64 {
            return 0.0;
        }
        self.data[y as usize * self.cols + x as usize]
    }
}

/// Where image point `(x, y)` of a `w × h` image falls on a map of `cols × rows` cells
/// (continuous cell coordinates, pixel centres at integers).
fn source(x: f32, y: f32, w: usize, h: usize, cols: usize, rows: usize) -> (f32, f32) {
    let gx = 2.0 * (x / (w as f32 - 1.0)) - 1.0;
    let gy = 2.0 * (y / (h as f32 - 1.0)) - 1.0;
    (
        ((gx + 1.0) * cols as f32 - 1.0) / 2.0,
        ((gy + 1.0) * rows as f32 - 1.0) / 2.0,
    )
}

/// Nearest sample (round half to even, zeros outside).
pub fn nearest(m: &Map, (x, y): (f32, f32), w: usize, h: usize) -> f32 {
    let (ix, iy) = source(x, y, w, h, m.cols, m.rows);
    m.at(ix.round_ties_even() as i64, iy.round_ties_even() as i64)
}

/// Bilinear sample (zeros outside).
pub fn bilinear(m: &Map, (x, y): (f32, f32), w: usize, h: usize) -> f32 {
    let (ix, iy) = source(x, y, w, h, m.cols, m.rows);
    let (x0, y0) = (ix.floor(), iy.floor());
    let (tx, ty) = (ix - x0, iy - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    m.at(x0, y0) * (1.0 - tx) * (1.0 - ty)
        + m.at(x0 + 1, y0) * tx * (1.0 - ty)
        + m.at(x0, y0 + 1) * (1.0 - tx) * ty
        + m.at(x0 + 1, y0 + 1) * tx * ty
}

/// Cubic convolution weights (A = −0.75, PyTorch's) of the 4 taps around fraction `t`.
fn cubic(t: f32) -> [f32; 4] {
    const A: f32 = -0.75;
    let near = |x: f32| ((A + 2.0) * x - (A + 3.0)) * x * x + 1.0;
    let far = |x: f32| ((A * x - 5.0 * A) * x + 8.0 * A) * x - 4.0 * A;
    [far(t + 1.0), near(t), near(1.0 - t), far(2.0 - t)]
}

/// Bicubic samples of every channel of `dense` (`channels × rows × cols`) at `(x, y)`,
/// zeros outside, appended to `out`.
pub fn bicubic(
    dense: &[f32],
    channels: usize,
    (rows, cols): (usize, usize),
    (x, y): (f32, f32),
    (w, h): (usize, usize),
    out: &mut Vec<f32>,
) {
    let (ix, iy) = source(x, y, w, h, cols, rows);
    let (fx, fy) = (ix.floor(), iy.floor());
    let (wx, wy) = (cubic(ix - fx), cubic(iy - fy));
    let (x0, y0) = (fx as i64 - 1, fy as i64 - 1);
    for c in 0..channels {
        let m = Map {
            data: &dense[c * rows * cols..(c + 1) * rows * cols],
            rows,
            cols,
        };
        let mut v = 0.0f32;
        for (i, wyi) in wy.iter().enumerate() {
            let row: f32 = (0..4)
                .map(|j| m.at(x0 + j as i64, y0 + i as i64) * wx[j])
                .sum();
            v += row * wyi;
        }
        out.push(v);
    }
}

/// The full-resolution keypoint heatmap (`8·hc × 8·wc`): per cell, the softmax of its 65
/// logits without the last ("no keypoint") channel, channel `8·r + c` at row `r`, column `c`
/// of the cell.
pub fn heatmap(logits: &[f32], hc: usize, wc: usize) -> Vec<f32> {
    let (rows, cols) = (hc * 8, wc * 8);
    let cells = hc * wc;
    let mut out = vec![0.0f32; rows * cols];
    for cy in 0..hc {
        for cx in 0..wc {
            let cell = cy * wc + cx;
            let logit = |k: usize| logits[k * cells + cell];
            let max = (0..65).map(logit).fold(f32::NEG_INFINITY, f32::max);
            let e: [f32; 65] = std::array::from_fn(|k| (logit(k) - max).exp());
            let sum: f32 = e.iter().sum();
            for (k, ek) in e[..64].iter().enumerate() {
                let (r, c) = (k / 8, k % 8);
                out[(cy * 8 + r) * cols + cx * 8 + c] = ek / sum;
            }
        }
    }
    out
}

/// Pixels that are the maximum of their `kernel × kernel` window and above `threshold`, in
/// row-major order, as `(x, y)`.
pub fn suppress(heat: &Map, kernel: usize, threshold: f32) -> Vec<(usize, usize)> {
    let r = (kernel / 2) as i64;
    let mut out = Vec::new();
    for y in 0..heat.rows {
        for x in 0..heat.cols {
            let v = heat.data[y * heat.cols + x];
            if v <= threshold {
                continue;
            }
            let (xi, yi) = (x as i64, y as i64);
            let is_max = (-r..=r).all(|dy| {
                (-r..=r).all(|dx| {
                    let (nx, ny) = (xi + dx, yi + dy);
                    nx < 0
                        || ny < 0
                        || nx >= heat.cols as i64
                        || ny >= heat.rows as i64
                        || heat.data[ny as usize * heat.cols + nx as usize] <= v
                })
            });
            if is_max {
                out.push((x, y));
            }
        }
    }
    out
}

/// Divides each of the `channels` values of every cell of `dense` by their norm (XFeat's
/// `F.normalize(M, dim=1)`, ε = 1e-12).
pub fn normalise_channels(dense: &mut [f32], channels: usize) {
    let cells = dense.len() / channels.max(1);
    for cell in 0..cells {
        let norm = (0..channels)
            .map(|c| dense[c * cells + cell].powi(2))
            .sum::<f32>()
            .sqrt()
            .max(1e-12);
        for c in 0..channels {
            dense[c * cells + cell] /= norm;
        }
    }
}

/// `v` divided by its norm (ε = 1e-12).
pub fn normalise(v: &mut [f32]) {
    let norm = v.iter().map(|x| x * x).sum::<f32>().sqrt().max(1e-12);
    v.iter_mut().for_each(|x| *x /= norm);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heatmap_unshuffles_cells_row_major() {
        // One cell: logit 10 at channel 8·2 + 5 → the peak at row 2, column 5.
        let mut logits = vec![0.0f32; 65];
        logits[8 * 2 + 5] = 10.0;
        let h = heatmap(&logits, 1, 1);
        let peak = (0..64).max_by(|&a, &b| h[a].total_cmp(&h[b])).unwrap();
        assert_eq!((peak / 8, peak % 8), (2, 5));
        let total: f32 = h.iter().sum::<f32>();
        assert!(total < 1.0 && total > 0.99, "{total}");
    }

    #[test]
    fn suppression_keeps_window_maxima_above_the_threshold() {
        let mut data = vec![0.0f32; 10 * 10];
        data[3 * 10 + 3] = 0.5;
        data[3 * 10 + 5] = 0.4; // within 2 px of a stronger one
        data[8 * 10 + 8] = 0.3;
        data[10 + 8] = 0.01; // row 1: below the threshold
        let m = Map {
            data: &data,
            rows: 10,
            cols: 10,
        };
        assert_eq!(suppress(&m, 5, 0.05), vec![(3, 3), (8, 8)]);
    }

    #[test]
    fn samplers_read_cell_values_at_their_centres() {
        // A 2×2 map behind an 16×16 image: image pixel 3.75 maps near cell 0's centre.
        let data = [1.0f32, 2.0, 3.0, 4.0];
        let m = Map {
            data: &data,
            rows: 2,
            cols: 2,
        };
        assert_eq!(nearest(&m, (0.0, 0.0), 16, 16), 1.0);
        assert_eq!(nearest(&m, (14.0, 14.0), 16, 16), 4.0);
        // The last pixel maps past the last cell's centre by half a cell: outside, as in
        // PyTorch's grid_sample (zeros).
        assert_eq!(nearest(&m, (15.0, 15.0), 16, 16), 0.0);
        let mid = bilinear(&m, (7.5, 7.5), 16, 16);
        assert!((mid - 2.5).abs() < 1e-5, "{mid}");
        let mut out = Vec::new();
        bicubic(&data, 1, (2, 2), (7.5, 7.5), (16, 16), &mut out);
        assert!(out[0] > 1.0 && out[0] < 4.0, "{out:?}");
    }
}
