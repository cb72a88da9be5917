//! A small RGB raster for overlays: pixels, blends, lines and circles, written as PNG.
//! Integer arithmetic only, so the same input always gives the same bytes.

use std::path::Path;

use anyhow::{Context, Result};

pub type Rgb = [u8; 3];

/// An RGB image, row-major, 3 bytes per pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Canvas {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<u8>,
}

impl Canvas {
    /// A canvas filled with `background`.
    pub fn new(width: usize, height: usize, background: Rgb) -> Self {
        Self {
            width,
            height,
            rgb: background.repeat(width * height),
        }
    }

    /// A grey canvas of `gray` (row-major, `width × height`), each pixel repeated `scale` times
    /// in x and y.
    pub fn from_gray(gray: &[u8], width: usize, height: usize, scale: usize) -> Self {
        let scale = scale.max(1);
        let mut c = Self::new(width * scale, height * scale, [0, 0, 0]);
        for y in 0..c.height {
            for x in 0..c.width {
                let v = gray
                    .get((y / scale) * width + x / scale)
                    .copied()
                    .unwrap_or(0);
                c.put(x, y, [v, v, v]);
            }
        }
        c
    }

    /// The colour at `(x, y)`, if inside.
    pub fn get(&self, x: usize, y: usize) -> Option<Rgb> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 3 * (y * self.width + x);
        Some([self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]])
    }

    fn put(&mut self, x: usize, y: usize, c: Rgb) {
        let i = 3 * (y * self.width + x);
        self.rgb[i..i + 3].copy_from_slice(&c);
    }

    /// Sets `(x, y)` to `c`; points outside are ignored.
    pub fn set(&mut self, x: i64, y: i64, c: Rgb) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            self.put(x as usize, y as usize, c);
        }
    }

    /// Mixes `c` into `(x, y)` with opacity `alpha` of 255.
    pub fn blend(&mut self, x: i64, y: i64, c: Rgb, alpha: u8) {
        if x < 0 || y < 0 {
            return;
        }
        let Some(old) = self.get(x as usize, y as usize) else {
            return;
        };
        let a = u32::from(alpha);
        let mix = |n: u8, o: u8| ((a * u32::from(n) + (255 - a) * u32::from(o) + 127) / 255) as u8;
        self.put(
            x as usize,
            y as usize,
            [mix(c[0], old[0]), mix(c[1], old[1]), mix(c[2], old[2])],
        );
    }

    /// A filled square of side `2 * half + 1` centred on `(x, y)`.
    pub fn dot(&mut self, x: i64, y: i64, half: i64, c: Rgb) {
        for dy in -half..=half {
            for dx in -half..=half {
                self.set(x + dx, y + dy, c);
            }
        }
    }

    /// A line from `(x0, y0)` to `(x1, y1)` (Bresenham).
    pub fn line(&mut self, (x0, y0): (i64, i64), (x1, y1): (i64, i64), c: Rgb) {
        let (dx, dy) = ((x1 - x0).abs(), -(y1 - y0).abs());
        let (sx, sy) = ((x1 - x0).signum(), (y1 - y0).signum());
        let (mut x, mut y, mut err) = (x0, y0, dx + dy);
        loop {
            self.set(x, y, c);
            if x == x1 && y == y1 {
                break;
            }
            let e2 = 2 * err;
            if e2 >= dy {
                err += dy;
                x += sx;
            }
            if e2 <= dx {
                err += dx;
                y += sy;
            }
        }
    }

    /// A circle outline of radius `r` centred on `(cx, cy)` (midpoint algorithm).
    pub fn circle(&mut self, cx: i64, cy: i64, r: i64, c: Rgb) {
        let (mut x, mut y, mut err) = (r.max(0), 0i64, 1 - r.max(0));
        while x >= y {
            for (px, py) in [
                (x, y),
                (y, x),
                (-y, x),
                (-x, y),
                (-x, -y),
                (-y, -x),
                (y, -x),
                (x, -y),
            ] {
                self.set(cx + px, cy + py, c);
            }
            y += 1;
            if err < 0 {
                err += 2 * y + 1;
            } else {
                x -= 1;
                err += 2 * (y - x) + 1;
            }
        }
    }

    /// The canvas as PNG bytes (RGB, 8 bits).
    pub fn png(&self) -> Result<Vec<u8>> {
        let size = (self.width as u32, self.height as u32);
        crate::plot_out::rgb_png(&self.rgb, size).context("encoding PNG")
    }

    /// Writes the canvas to `path` as PNG.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        std::fs::write(path, self.png()?).with_context(|| format!("writing {}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_and_line_hit_their_end_points() {
        let mut c = Canvas::new(21, 21, [0, 0, 0]);
        c.circle(10, 10, 5, [255, 0, 0]);
        for (x, y) in [(15, 10), (5, 10), (10, 15), (10, 5)] {
            assert_eq!(c.get(x, y), Some([255, 0, 0]), "({x}, {y})");
        }
        assert_eq!(c.get(10, 10), Some([0, 0, 0]));
        c.line((0, 0), (20, 7), [0, 255, 0]);
        assert_eq!(c.get(0, 0), Some([0, 255, 0]));
        assert_eq!(c.get(20, 7), Some([0, 255, 0]));
    }

    #[test]
    fn blend_mixes_and_outside_is_ignored() {
        let mut c = Canvas::new(2, 1, [100, 100, 100]);
        c.blend(0, 0, [255, 0, 0], 255);
        c.blend(1, 0, [200, 0, 0], 128);
        c.set(-1, 0, [1, 2, 3]);
        c.blend(5, 5, [1, 2, 3], 10);
        assert_eq!(c.get(0, 0), Some([255, 0, 0]));
        assert_eq!(c.get(1, 0), Some([150, 50, 50]));
    }

    #[test]
    fn gray_is_scaled_by_repetition() {
        let c = Canvas::new(1, 1, [0; 3]);
        assert_eq!(c.rgb.len(), 3);
        let g = Canvas::from_gray(&[10, 20], 2, 1, 2);
        assert_eq!((g.width, g.height), (4, 2));
        assert_eq!(g.get(1, 1), Some([10, 10, 10]));
        assert_eq!(g.get(2, 0), Some([20, 20, 20]));
    }
}
