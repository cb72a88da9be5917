//! 8-bit images made from frame channels, the input of detectors and descriptors.

use crate::Channel;

/// An 8-bit image with `channels` interleaved planes (1 for classic detectors, 2 for a
/// two-channel SuperPoint). Row `y` starts at byte `y * stride`.
///
/// `scale_x`/`scale_y` map image pixels back to the frame grid:
/// `col = x * scale_x`, `row = y * scale_y`.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub channels: usize,
    pub stride: usize,
    pub data: Vec<u8>,
    /// The frame channels this image was made from, one per plane.
    pub sources: Vec<Channel>,
    pub scale_x: f64,
    pub scale_y: f64,
}

impl Image {
    /// A black single-plane image.
    pub fn new_gray(width: usize, height: usize, source: Channel) -> Self {
        Self {
            width,
            height,
            channels: 1,
            stride: width,
            data: vec![0; width * height],
            sources: vec![source],
            scale_x: 1.0,
            scale_y: 1.0,
        }
    }

    /// The image's name: its source channels joined by `+` (`signal`, `signal+range`). Per-image
    /// settings (`[detector.by_image.<name>]`, downsampler windows) refer to images by it.
    pub fn name(&self) -> String {
        let names: Vec<&str> = self.sources.iter().map(|c| c.name()).collect();
        names.join("+")
    }

    /// Pixel value of plane 0 at `(x, y)`, if inside.
    pub fn get(&self, x: usize, y: usize) -> Option<u8> {
        if x >= self.width || y >= self.height {
            return None;
        }
        self.data.get(y * self.stride + x * self.channels).copied()
    }

    /// Frame-grid pixel `(row, col)` nearest to image point `(x, y)`, clamped to the grid.
    pub fn to_grid(&self, x: f64, y: f64, rows: usize, cols: usize) -> (usize, usize) {
        let clamp = |v: f64, n: usize| (v.round().max(0.0) as usize).min(n.saturating_sub(1));
        (clamp(y * self.scale_y, rows), clamp(x * self.scale_x, cols))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_image_points_to_grid() {
        let mut img = Image::new_gray(1024, 64, Channel::Signal);
        img.scale_x = 2.0;
        img.scale_y = 2.0;
        assert_eq!(img.to_grid(10.2, 3.0, 128, 2048), (6, 20));
        assert_eq!(img.to_grid(5000.0, -3.0, 128, 2048), (0, 2047));
        assert_eq!(img.get(0, 0), Some(0));
        assert_eq!(img.get(1024, 0), None);
    }
}
