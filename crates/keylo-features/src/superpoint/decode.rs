//! SuperPoint's outputs to keypoints and descriptors: softmax over the 65 detector channels,
//! depth-to-space, non-maximum suppression, border removal, top-k, and bilinear descriptor
//! sampling. Pure functions over plain buffers, so they are tested without ONNX Runtime.

use std::cmp::Ordering;

use keylo_core::Keypoint;

use super::params::Nms;

/// Side of a detector cell (the network's total stride).
pub const CELL: usize = 8;
/// Detector channels: one per cell pixel plus the "no keypoint" dustbin.
pub const DETECTOR_CHANNELS: usize = CELL * CELL + 1;

/// The keypoint probability of every pixel of a `(8·hc)×(8·wc)` image from the detector
/// logits `scores` (`65 × hc × wc`, channel-major): softmax over the 65 channels of each cell,
/// dustbin dropped, channel `dy·8 + dx` placed at pixel `(8·cx + dx, 8·cy + dy)`.
pub fn heatmap(scores: &[f32], hc: usize, wc: usize) -> Vec<f32> {
    let (h, w) = (hc * CELL, wc * CELL);
    let plane = hc * wc;
    let mut heat = vec![0.0f32; h * w];
    if scores.len() < DETECTOR_CHANNELS * plane {
        return heat;
    }
    let mut cell = [0.0f32; DETECTOR_CHANNELS];
    for cy in 0..hc {
        for cx in 0..wc {
            let at = cy * wc + cx;
            for (c, v) in cell.iter_mut().enumerate() {
                *v = scores[c * plane + at];
            }
            let max = cell.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            let mut sum = 0.0f32;
            for v in cell.iter_mut() {
                *v = (*v - max).exp();
                sum += *v;
            }
            for (c, v) in cell[..CELL * CELL].iter().enumerate() {
                let (dy, dx) = (c / CELL, c % CELL);
                heat[(cy * CELL + dy) * w + cx * CELL + dx] = v / sum;
            }
        }
    }
    heat
}

/// What survives suppression and selection.
#[derive(Debug, Clone, Copy)]
pub struct Selection {
    /// Smallest probability kept.
    pub threshold: f32,
    /// Suppression rule and radius.
    pub nms: Nms,
    /// Radius in pixels (inf-norm) of suppression; 0 turns it off.
    pub nms_radius: usize,
    /// Pixels at the image border where keypoints are dropped.
    pub border: usize,
    /// Most keypoints kept, strongest first (0: all).
    pub max_keypoints: usize,
}

/// Keypoints of a `w×h` heatmap inside the valid `valid_w×valid_h` top-left part (the rest
/// is padding), strongest first; ties broken by row, then column, so the order is fixed.
pub fn select(
    heat: &[f32],
    w: usize,
    h: usize,
    valid: (usize, usize),
    s: &Selection,
) -> Vec<Keypoint> {
    let (valid_w, valid_h) = (valid.0.min(w), valid.1.min(h));
    let kept = match s.nms {
        Nms::MaxPool => max_pool_nms(heat, w, h, s.nms_radius),
        Nms::Greedy => greedy_nms(heat, w, h, s.nms_radius, s.threshold),
    };
    let b = s.border;
    let mut points: Vec<(f32, usize, usize)> = Vec::new();
    for y in b..valid_h.saturating_sub(b) {
        for x in b..valid_w.saturating_sub(b) {
            let i = y * w + x;
            if kept[i] && heat[i] > s.threshold {
                points.push((heat[i], y, x));
            }
        }
    }
    points.sort_by(|a, b| {
        b.0.partial_cmp(&a.0)
            .unwrap_or(Ordering::Equal)
            .then(a.1.cmp(&b.1))
            .then(a.2.cmp(&b.2))
    });
    if s.max_keypoints > 0 {
        points.truncate(s.max_keypoints);
    }
    points
        .into_iter()
        .map(|(score, y, x)| Keypoint {
            x: x as f32,
            y: y as f32,
            size: CELL as f32,
            angle: -1.0,
            response: score,
            octave: 0,
            class_id: -1,
        })
        .collect()
}

/// `out[i]`: the maximum of `values` over the `(2r+1)²` window around pixel `i` (clipped at
/// the borders), computed separably with whole-row element-wise maxima (vectorised).
fn max_filter<T: Copy + PartialOrd>(values: &[T], w: usize, h: usize, r: usize) -> Vec<T> {
    #[inline(always)]
    fn merge<T: Copy + PartialOrd>(out: &mut [T], other: &[T]) {
        let n = out.len().min(other.len());
        let (out, other) = (&mut out[..n], &other[..n]);
        for i in 0..n {
            let (o, v) = (out[i], other[i]);
            out[i] = if v > o { v } else { o };
        }
    }
    let mut rows = values.to_vec();
    for d in 1..=r.min(w.saturating_sub(1)) {
        for y in 0..h {
            let line = &values[y * w..(y + 1) * w];
            let out = &mut rows[y * w..(y + 1) * w];
            merge(&mut out[..w - d], &line[d..]);
            merge(&mut out[d..], &line[..w - d]);
        }
    }
    let mut out = rows.clone();
    for (y, target) in out.chunks_exact_mut(w).enumerate() {
        let lo = y.saturating_sub(r);
        let hi = (y + r).min(h - 1);
        for yy in (lo..=hi).filter(|&yy| yy != y) {
            merge(target, &rows[yy * w..(yy + 1) * w]);
        }
    }
    out
}

/// The max-pool NMS of rpautrat's and SuperGlue's SuperPoint: a pixel is kept when it is the
/// maximum of its window; then, twice, pixels outside every kept pixel's window that are the
/// maximum of their window among the remaining scores are added.
fn max_pool_nms(heat: &[f32], w: usize, h: usize, r: usize) -> Vec<bool> {
    if r == 0 || w == 0 || h == 0 {
        return vec![true; heat.len()];
    }
    let pooled = max_filter(heat, w, h, r);
    let mut keep: Vec<u8> = heat
        .iter()
        .zip(&pooled)
        .map(|(v, m)| u8::from(v == m))
        .collect();
    let mut remaining = vec![0.0f32; heat.len()];
    for _ in 0..2 {
        let suppressed = max_filter(&keep, w, h, r);
        for ((r, &v), &s) in remaining.iter_mut().zip(heat).zip(&suppressed) {
            *r = if s > 0 { 0.0 } else { v };
        }
        let pooled = max_filter(&remaining, w, h, r);
        for i in 0..keep.len() {
            if suppressed[i] == 0 && remaining[i] == pooled[i] {
                keep[i] = 1;
            }
        }
    }
    keep.into_iter().map(|k| k > 0).collect()
}

/// Magic Leap's grid NMS: candidates above `threshold`, strongest first, each kept one
/// suppresses every other candidate within the inf-norm radius `r`.
fn greedy_nms(heat: &[f32], w: usize, h: usize, r: usize, threshold: f32) -> Vec<bool> {
    let mut candidates: Vec<usize> = (0..w * h).filter(|&i| heat[i] > threshold).collect();
    candidates.sort_by(|&a, &b| {
        heat[b]
            .partial_cmp(&heat[a])
            .unwrap_or(Ordering::Equal)
            .then(a.cmp(&b))
    });
    let mut keep = vec![false; w * h];
    let mut blocked = vec![false; w * h];
    for i in candidates {
        if blocked[i] {
            continue;
        }
        keep[i] = true;
        let (y, x) = (i / w, i % w);
        for yy in y.saturating_sub(r)..=(y + r).min(h - 1) {
            for xx in x.saturating_sub(r)..=(x + r).min(w - 1) {
                blocked[yy * w + xx] = true;
            }
        }
    }
    keep
}

/// The dense descriptor map (`dim × hc × wc`, channel-major) sampled bilinearly at each
/// keypoint, then L2-normalised: pixel `x` sits at cell coordinate `(x + 0.5)/8 − 0.5`
/// (cell centres, `grid_sample` with `align_corners = false`), and samples outside the map
/// count as zero, as in the reference implementations. Row `i` describes `keypoints[i]`.
pub fn sample_descriptors(
    dense: &[f32],
    dim: usize,
    hc: usize,
    wc: usize,
    keypoints: &[Keypoint],
) -> Vec<f32> {
    let plane = hc * wc;
    let mut out = vec![0.0f32; keypoints.len() * dim];
    if dense.len() < dim * plane {
        return out;
    }
    for (k, row) in keypoints.iter().zip(out.chunks_exact_mut(dim)) {
        let u = (f64::from(k.x) + 0.5) / CELL as f64 - 0.5;
        let v = (f64::from(k.y) + 0.5) / CELL as f64 - 0.5;
        let (u0, v0) = (u.floor(), v.floor());
        let (fu, fv) = ((u - u0) as f32, (v - v0) as f32);
        let corners = [
            (u0, v0, (1.0 - fu) * (1.0 - fv)),
            (u0 + 1.0, v0, fu * (1.0 - fv)),
            (u0, v0 + 1.0, (1.0 - fu) * fv),
            (u0 + 1.0, v0 + 1.0, fu * fv),
        ];
        for (cu, cv, weight) in corners {
            if weight == 0.0 || cu < 0.0 || cv < 0.0 || cu >= wc as f64 || cv >= hc as f64 {
                continue;
            }
            let at = cv as usize * wc + cu as usize;
            for (c, d) in row.iter_mut().enumerate() {
                *d += weight * dense[c * plane + at];
            }
        }
        let norm = row.iter().map(|d| d * d).sum::<f32>().sqrt();
        if norm > 1e-12 {
            row.iter_mut().for_each(|d| *d /= norm);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn selection(nms: Nms, r: usize) -> Selection {
        Selection {
            threshold: 0.01,
            nms,
            nms_radius: r,
            border: 0,
            max_keypoints: 0,
        }
    }

    #[test]
    fn heatmap_places_cell_channels_and_sums_with_dustbin_to_one() {
        let (hc, wc) = (2, 3);
        let plane = hc * wc;
        let mut scores = vec![0.0f32; DETECTOR_CHANNELS * plane];
        // Cell (cx = 2, cy = 1): channel 8·3 + 5 (dy = 3, dx = 5) strongly on.
        scores[(3 * CELL + 5) * plane + wc + 2] = 10.0;
        let heat = heatmap(&scores, hc, wc);
        let w = wc * CELL;
        let peak = heat[(CELL + 3) * w + 2 * CELL + 5];
        let expected = 10f32.exp() / (10f32.exp() + 64.0);
        assert!((peak - expected).abs() < 1e-6, "{peak} vs {expected}");
        // Every cell: 64 pixels plus the dustbin share sum to 1.
        let cell_sum: f32 = (0..CELL)
            .flat_map(|dy| (0..CELL).map(move |dx| (dy, dx)))
            .map(|(dy, dx)| heat[dy * w + dx])
            .sum();
        assert!((cell_sum - 64.0 / 65.0).abs() < 1e-5, "{cell_sum}");
    }

    #[test]
    fn both_nms_rules_keep_one_peak_per_radius_and_far_peaks_both() {
        let (w, h) = (32, 16);
        let mut heat = vec![0.0f32; w * h];
        heat[5 * w + 5] = 0.9;
        heat[6 * w + 7] = 0.5; // within radius 4 of the first
        heat[5 * w + 20] = 0.4; // far
        for nms in [Nms::MaxPool, Nms::Greedy] {
            let k = select(&heat, w, h, (w, h), &selection(nms, 4));
            let at: Vec<(f32, f32)> = k.iter().map(|k| (k.x, k.y)).collect();
            assert_eq!(at, vec![(5.0, 5.0), (20.0, 5.0)], "{nms:?}");
            assert!(k[0].response > k[1].response);
        }
    }

    #[test]
    fn max_pool_rule_recovers_a_peak_only_suppressed_by_a_suppressed_pixel() {
        // 0.8 (x = 2) lies within radius 2 of 0.9 (x = 0) and is suppressed; 0.7 (x = 4) is
        // not a window maximum at first (0.8 is in its window) but lies outside 0.9's window:
        // the refinement passes of max-pool NMS add it, and greedy NMS keeps it too.
        let (w, h) = (16, 1);
        let mut heat = vec![0.0f32; w * h];
        heat[0] = 0.9;
        heat[2] = 0.8;
        heat[4] = 0.7;
        for nms in [Nms::MaxPool, Nms::Greedy] {
            let k = select(&heat, w, h, (w, h), &selection(nms, 2));
            let xs: Vec<f32> = k.iter().map(|k| k.x).collect();
            assert_eq!(xs, vec![0.0, 4.0], "{nms:?}");
        }
    }

    #[test]
    fn border_padding_threshold_and_cap_are_applied() {
        let (w, h) = (24, 16);
        let mut heat = vec![0.0f32; w * h];
        heat[w + 1] = 0.9; // inside the 4 px border
        heat[8 * w + 10] = 0.8;
        heat[8 * w + 20] = 0.85; // in the padding (valid width 16)
        heat[12 * w + 6] = 0.005; // below threshold
        heat[5 * w + 5] = 0.3;
        let mut s = selection(Nms::MaxPool, 1);
        s.border = 4;
        let k = select(&heat, w, h, (16, 16), &s);
        assert_eq!(
            k.iter().map(|k| (k.x, k.y)).collect::<Vec<_>>(),
            vec![(10.0, 8.0), (5.0, 5.0)]
        );
        s.max_keypoints = 1;
        assert_eq!(select(&heat, w, h, (16, 16), &s).len(), 1);
    }

    #[test]
    fn descriptors_interpolate_between_cell_centres_and_are_unit_length() {
        let (dim, hc, wc) = (2, 2, 2);
        let plane = hc * wc;
        // Channel 0 = 1 everywhere; channel 1 = cell column (0 or 1).
        let mut dense = vec![0.0f32; dim * plane];
        for at in 0..plane {
            dense[at] = 1.0;
            dense[plane + at] = (at % wc) as f32;
        }
        // x = 7.5 is halfway between the centres of cell columns 0 (x = 3.5) and 1 (x = 11.5).
        let k = Keypoint {
            x: 7.5,
            y: 3.5,
            ..Keypoint::default()
        };
        let d = sample_descriptors(&dense, dim, hc, wc, &[k]);
        let expected = [1.0 / 1.25f32.sqrt(), 0.5 / 1.25f32.sqrt()];
        assert!(
            (d[0] - expected[0]).abs() < 1e-6 && (d[1] - expected[1]).abs() < 1e-6,
            "{d:?}"
        );
        // At a cell centre the sample is that cell's vector.
        let k = Keypoint {
            x: 11.5,
            y: 11.5,
            ..Keypoint::default()
        };
        let d = sample_descriptors(&dense, dim, hc, wc, &[k]);
        assert!(
            (d[0] - 0.5f32.sqrt()).abs() < 1e-6 && (d[1] - 0.5f32.sqrt()).abs() < 1e-6,
            "{d:?}"
        );
    }
}
