//! Synthetic images for the native descriptors' unit tests.

use keylo_core::{Channel, Image, Keypoint};

/// A smooth random-looking texture: a sum of Gaussian blobs around `(cx, cy)`, sampled with
/// the scene turned by `degrees` about that point (so rotating the scene rotates the image).
pub fn blobs(w: usize, h: usize, cx: f32, cy: f32, degrees: f32) -> Image {
    let mut img = Image::new_gray(w, h, Channel::Signal);
    let (s, c) = degrees.to_radians().sin_cos();
    let blobs: Vec<(f32, f32, f32, f32)> = (0..60u32)
        .map(|i| {
            let r = |k: u32| ((i * 7919 + k * 104729) % 1000) as f32 / 1000.0;
            let (x, y) = ((r(1) - 0.5) * 44.0, (r(2) - 0.5) * 44.0);
            (x, y, 1.5 + 3.0 * r(3), (r(4) - 0.4) * 200.0)
        })
        .collect();
    for y in 0..h {
        for x in 0..w {
            // Scene point seen at this pixel: turn back by the rotation.
            let (dx, dy) = (x as f32 - cx, y as f32 - cy);
            let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
            let mut val = 100.0;
            for &(bx, by, sig, amp) in &blobs {
                let d2 = (u - bx).powi(2) + (v - by).powi(2);
                val += amp * (-d2 / (2.0 * sig * sig)).exp();
            }
            img.data[y * w + x] = val.clamp(0.0, 255.0) as u8;
        }
    }
    img
}

/// A keypoint at `(x, y)` of size 7 (FAST's).
pub fn keypoint(x: f32, y: f32) -> Keypoint {
    Keypoint {
        x,
        y,
        size: 7.0,
        angle: -1.0,
        ..Keypoint::default()
    }
}

/// Hamming distance between two rows.
pub fn hamming(a: &[u8], b: &[u8]) -> u32 {
    a.iter().zip(b).map(|(x, y)| (x ^ y).count_ones()).sum()
}
