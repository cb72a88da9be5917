//! Whole-simulator tests of the `ouster` appearance: the measured signal level, the four-beam
//! gain pattern and the noise of a still sensor (with its partial drops), deterministic; a
//! still sensor stays still.

use keylo_core::LidarFrame;

use crate::{Appearance, SceneKind, SimConfig, Simulator};

/// A still OS0-128 in the lab (no walking, no sway).
fn still(appearance: Appearance, frames: usize) -> Simulator {
    Simulator::new(&SimConfig {
        scene: SceneKind::Lab,
        frames,
        columns: 512,
        speed_scale: 0.0,
        sway_scale: 0.0,
        appearance,
        ..SimConfig::default()
    })
    .unwrap()
}

fn median(mut v: Vec<f32>) -> f32 {
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

fn valid_signal(f: &LidarFrame) -> Vec<f32> {
    f.signal
        .iter()
        .zip(&f.valid)
        .filter(|(_, ok)| **ok)
        .map(|(s, _)| *s)
        .collect()
}

/// The `q`-th quantile (0–1) of `v`.
fn quantile(mut v: Vec<f32>, q: f64) -> f32 {
    v.sort_by(f32::total_cmp);
    v[((v.len() - 1) as f64 * q) as usize]
}

#[test]
fn ouster_signal_is_at_the_real_level_and_deterministic() {
    let sim = still(Appearance::Ouster, 2);
    let f = sim.frame(0);
    assert_eq!(f, still(Appearance::Ouster, 2).frame(0));
    // One count reads grey 17 in the real images: their 90th percentile is about 200 counts.
    let signal = valid_signal(&f);
    let p90 = quantile(signal.clone(), 0.9);
    assert!(
        (120.0..350.0).contains(&p90),
        "90th percentile {p90} counts"
    );
    // Every reported return has a count; weak ones have only a few.
    assert!(signal.iter().all(|&s| s >= 1.0));
    assert!(quantile(signal, 0.02) <= 4.0);
    // The ideal model's counts are the shading model's photons, far more.
    let ideal = quantile(valid_signal(&still(Appearance::Ideal, 1).frame(0)), 0.9);
    assert!(ideal > 10.0 * p90, "ideal 90th percentile {ideal}");
}

#[test]
fn ouster_rows_show_the_four_beam_pattern() {
    let f = still(Appearance::Ouster, 1).frame(0);
    let row_mean = |r: usize| -> f64 {
        let row = &f.signal[r * f.cols..(r + 1) * f.cols];
        row.iter().map(|&s| f64::from(s)).sum::<f64>() / f.cols as f64
    };
    // Rows 44..100: every fourth beam (phase 3) is the weak one, 0.75–0.87 of the others in
    // grey, so 0.65–0.81 in counts (the gains' 1.5th power).
    let (mut weak, mut other) = (0.0, 0.0);
    for r in 44..100 {
        if r % 4 == 3 {
            weak += row_mean(r) / 14.0;
        } else {
            other += row_mean(r) / 42.0;
        }
    }
    let ratio = weak / other;
    assert!((0.6..0.88).contains(&ratio), "weak/other beams {ratio}");
}

#[test]
fn still_ouster_frames_differ_by_the_measured_noise() {
    let sim = still(Appearance::Ouster, 2);
    let (a, b) = (sim.frame(0), sim.frame(1));
    assert_eq!(a.range.len(), b.range.len());
    // Still sensor: the same pixels return; only the noise differs.
    let mut z = Vec::new();
    for i in 0..a.signal.len() {
        let (sa, sb) = (f64::from(a.signal[i]), f64::from(b.signal[i]));
        let mean = 0.5 * (sa + sb);
        if a.valid[i] && b.valid[i] && (20.0..200.0).contains(&mean) {
            // (a − b) / √2 has the variance of one frame's noise: the mean (shot noise).
            z.push(((sa - sb) / (2.0 * mean).sqrt()) as f32);
        }
    }
    assert!(z.len() > 10_000, "{}", z.len());
    // Robust σ (median |z| · 1.4826): partial drops put a heavy tail on the differences, as
    // in the real images, which a plain standard deviation would count as noise.
    let tail = z.iter().filter(|v| v.abs() > 6.0).count() as f64 / z.len() as f64;
    let sd = f64::from(median(z.iter().map(|v| v.abs()).collect())) * 1.4826;
    assert!((0.85..1.15).contains(&sd), "noise over the model's: {sd}");
    // Gaussian noise alone: 2e-9 beyond 6 σ; partial drops: a few tenths of a percent.
    assert!((0.0005..0.02).contains(&tail), "share beyond 6 σ: {tail}");
}

#[test]
fn still_sensor_does_not_move() {
    let sim = still(Appearance::Ideal, 3);
    let gt = sim.ground_truth();
    for p in &gt.poses {
        assert!((p.translation.vector - gt.poses[0].translation.vector).norm() < 1e-12);
        assert!(p.rotation.angle_to(&gt.poses[0].rotation) < 1e-12);
    }
}
