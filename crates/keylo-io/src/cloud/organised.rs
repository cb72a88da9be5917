//! Organised clouds (one point per pixel, row-major, row 0 the top beam, as ouster-ros
//! publishes them) become a frame pixel for pixel.

use std::sync::Arc;

use keylo_core::{BeamGeometry, LidarFrame};
use nalgebra::Point3;

use super::RawCloud;

/// The frame of an organised cloud: pixel `i` is point `i`. A pixel is valid when its point
/// is finite and not at the origin (drivers mark "no return" either way).
///
/// Column times are the earliest point time of each column (the cloud time when the cloud
/// has no time field). Missing channels are zero; signal falls back to intensity, which is
/// what drivers without a separate signal field publish.
pub fn to_frame(
    cloud: &RawCloud,
    rows: usize,
    cols: usize,
    index: u64,
    beams: Arc<BeamGeometry>,
) -> LidarFrame {
    let mut f = LidarFrame::empty(index, cloud.timestamp, rows, cols, beams);
    for (i, p) in cloud.points.iter().enumerate().take(rows * cols) {
        let point = Point3::new(p[0], p[1], p[2]);
        let norm = point.coords.norm();
        if !norm.is_finite() || norm == 0.0 {
            continue;
        }
        f.valid[i] = true;
        f.points[i] = point;
        f.range[i] = cloud.range.as_ref().map_or(norm, |r| r[i]);
    }
    copy_channel(cloud.intensity.as_deref(), &mut f.signal);
    copy_channel(cloud.reflectivity.as_deref(), &mut f.reflectivity);
    copy_channel(cloud.near_ir.as_deref(), &mut f.near_ir);
    if let Some(times) = &cloud.time {
        f.column_times = column_times(
            cloud.timestamp,
            cols,
            times.iter().enumerate().map(|(i, t)| (i % cols, *t)),
        );
    }
    f
}

fn copy_channel(src: Option<&[f32]>, dst: &mut [f32]) {
    if let Some(src) = src {
        for (d, s) in dst.iter_mut().zip(src) {
            *d = if s.is_finite() { *s } else { 0.0 };
        }
    }
}

/// Per-column times from `(column, time relative to t0)` pairs: the earliest time of each
/// column; columns without any time are interpolated linearly between their neighbours
/// (held constant past the ends, `t0` when nothing is known).
pub fn column_times(t0: f64, cols: usize, samples: impl Iterator<Item = (usize, f64)>) -> Vec<f64> {
    let mut best = vec![f64::INFINITY; cols];
    for (c, t) in samples {
        if let Some(b) = best.get_mut(c) {
            if t.is_finite() && t < *b {
                *b = t;
            }
        }
    }
    let known: Vec<usize> = (0..cols).filter(|&c| best[c].is_finite()).collect();
    let (Some(&first), Some(&last)) = (known.first(), known.last()) else {
        return vec![t0; cols];
    };
    let mut out = vec![0.0; cols];
    for w in known.windows(2) {
        let (a, b) = (w[0], w[1]);
        for (c, o) in out.iter_mut().enumerate().take(b).skip(a) {
            let s = (c - a) as f64 / (b - a) as f64;
            *o = best[a] + s * (best[b] - best[a]);
        }
    }
    for (c, o) in out.iter_mut().enumerate() {
        if c <= first {
            *o = best[first];
        } else if c >= last {
            *o = best[last];
        }
    }
    out.iter().map(|t| t0 + t).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_times_take_the_earliest_and_fill_gaps() {
        let t = column_times(10.0, 5, [(1, 0.2), (1, 0.1), (3, 0.3)].into_iter());
        let want = [10.1, 10.1, 10.2, 10.3, 10.3];
        for (a, b) in t.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{t:?}");
        }
        assert_eq!(column_times(1.0, 2, std::iter::empty()), vec![1.0, 1.0]);
    }

    #[test]
    fn organised_pixels_map_one_to_one() {
        let beams = Arc::new(BeamGeometry {
            model: "t".into(),
            altitude_deg: vec![0.0],
            azimuth_deg: vec![0.0],
            origin_to_beam_mm: 0.0,
            columns_per_frame: 3,
            frame_rate_hz: 10.0,
            column_lag_by_row: Vec::new(),
        });
        let cloud = RawCloud {
            timestamp: 2.0,
            points: vec![[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0]],
            intensity: Some(vec![5.0, 6.0, 7.0]),
            time: Some(vec![0.0, 0.01, 0.02]),
            grid: Some((1, 3)),
            ..RawCloud::default()
        };
        let f = to_frame(&cloud, 1, 3, 4, beams);
        assert_eq!(f.valid, vec![true, false, false]);
        assert_eq!(f.range[0], 1.0);
        assert_eq!(f.signal, vec![5.0, 6.0, 7.0]);
        assert!((f.column_times[2] - 2.02).abs() < 1e-12);
        assert!((f.pixel_time(1) - 2.01).abs() < 1e-12);
    }
}
