//! A detector's image with what the pipeline made of it: the pixels whose points the
//! downsampler kept (tinted), every keypoint (a circle of its size, a line along its
//! orientation) and its position (a red dot).

use keylo::Keypoint;

use super::canvas::{Canvas, Rgb};

/// Tint of the image pixels whose frame points went to the registrar.
pub const KEPT: Rgb = [0, 190, 255];
/// Opacity of that tint, of 255.
pub const KEPT_ALPHA: u8 = 110;
/// Keypoint circles and orientation lines.
pub const OUTLINE: Rgb = [255, 210, 0];
/// The keypoint's own pixel.
pub const CENTRE: Rgb = [255, 40, 40];

/// An 8-bit image and the keypoints found in it.
pub struct ImageView<'a> {
    pub gray: &'a [u8],
    pub width: usize,
    pub height: usize,
    /// Image → frame grid: `col = x * scale_x`, `row = y * scale_y`.
    pub scale_x: f64,
    pub scale_y: f64,
    pub keypoints: &'a [Keypoint],
}

/// The frame-grid pixels a downsampler kept: row-major indices into `rows × cols`.
pub struct Kept<'a> {
    pub pixels: &'a [usize],
    pub rows: usize,
    pub cols: usize,
}

/// The first plane of `image`, row-major without padding.
fn first_plane(image: &keylo::Image) -> Vec<u8> {
    (0..image.height)
        .flat_map(|y| (0..image.width).map(move |x| (x, y)))
        .map(|(x, y)| image.get(x, y).unwrap_or(0))
        .collect()
}

/// Draws a detector's `image` (its first plane) with `keypoints` and the `kept` pixels.
pub fn draw_image(image: &keylo::Image, keypoints: &[Keypoint], kept: Option<&Kept>) -> Canvas {
    let gray = first_plane(image);
    let view = ImageView {
        gray: &gray,
        width: image.width,
        height: image.height,
        scale_x: image.scale_x,
        scale_y: image.scale_y,
        keypoints,
    };
    draw(&view, kept)
}

/// Canvas pixels per image pixel: images under 128 rows (the paper's 1024×64) are drawn
/// twice as large so that markers stay legible.
pub fn zoom(height: usize) -> usize {
    if height < 128 {
        2
    } else {
        1
    }
}

/// Canvas coordinate of image coordinate `v` (the centre of pixel `v` for whole `v`).
pub fn to_canvas(v: f32, zoom: usize) -> i64 {
    (f64::from(v) * zoom as f64 + zoom as f64 / 2.0).floor() as i64
}

/// Draws the view; `kept`, when given, is tinted under the keypoints.
pub fn draw(view: &ImageView, kept: Option<&Kept>) -> Canvas {
    let z = zoom(view.height);
    let mut canvas = Canvas::from_gray(view.gray, view.width, view.height, z);
    if let Some(k) = kept {
        tint_kept(&mut canvas, view, k, z);
    }
    let z = z as f32;
    let marks: Vec<(i64, i64, &Keypoint)> = view
        .keypoints
        .iter()
        .filter(|kp| kp.x.is_finite() && kp.y.is_finite())
        .map(|kp| (to_canvas(kp.x, z as usize), to_canvas(kp.y, z as usize), kp))
        .collect();
    // A circle never needs to be larger than the picture (a plugin's size may be anything).
    let largest = (canvas.width + canvas.height) as f32;
    for &(x, y, kp) in &marks {
        let size = if kp.size.is_finite() { kp.size } else { 0.0 };
        let r = ((size.max(0.0) / 2.0 * z).min(largest).round() as i64).max(3);
        canvas.circle(x, y, r, OUTLINE);
        if kp.angle >= 0.0 && kp.angle.is_finite() {
            let a = f64::from(kp.angle).to_radians();
            let end = (
                x + (r as f64 * a.cos()).round() as i64,
                y + (r as f64 * a.sin()).round() as i64,
            );
            canvas.line((x, y), end, OUTLINE);
        }
    }
    for &(x, y, _) in &marks {
        canvas.dot(x, y, 1, CENTRE);
    }
    canvas
}

/// Tints, once each, the canvas pixels covering the kept grid pixels.
fn tint_kept(canvas: &mut Canvas, view: &ImageView, kept: &Kept, zoom: usize) {
    let (w, h) = (canvas.width, canvas.height);
    let mut mask = vec![false; w * h];
    let span = |start: f64, end: f64, n: usize| {
        let a = (start * zoom as f64).floor().max(0.0) as usize;
        let b = ((end * zoom as f64).floor() as usize)
            .max(a.saturating_add(1))
            .min(n);
        a..b
    };
    let scales_ok = [view.scale_x, view.scale_y]
        .iter()
        .all(|s| s.is_finite() && *s > 0.0);
    if !scales_ok {
        return;
    }
    for &i in kept.pixels {
        if kept.cols == 0 || i >= kept.rows * kept.cols {
            continue;
        }
        let (row, col) = ((i / kept.cols) as f64, (i % kept.cols) as f64);
        let xs = span(col / view.scale_x, (col + 1.0) / view.scale_x, w);
        for y in span(row / view.scale_y, (row + 1.0) / view.scale_y, h) {
            for x in xs.clone() {
                mask[y * w + x] = true;
            }
        }
    }
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        canvas.blend((i % w) as i64, (i / w) as i64, KEPT, KEPT_ALPHA);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kp(x: f32, y: f32, size: f32, angle: f32) -> Keypoint {
        Keypoint {
            x,
            y,
            size,
            angle,
            response: 1.0,
            octave: 0,
            class_id: -1,
        }
    }

    #[test]
    fn keypoints_and_kept_pixels_land_where_they_belong() {
        let gray = vec![100u8; 40 * 8];
        let kps = [kp(10.0, 4.0, 8.0, 0.0), kp(30.0, 2.0, 0.0, -1.0)];
        let view = ImageView {
            gray: &gray,
            width: 40,
            height: 8,
            scale_x: 2.0,
            scale_y: 2.0,
            keypoints: &kps,
        };
        // Grid pixel (row 0, col 0) of a 16 × 80 grid is image pixel (0, 0).
        let kept = Kept {
            pixels: &[0],
            rows: 16,
            cols: 80,
        };
        let c = draw(&view, Some(&kept));
        assert_eq!((c.width, c.height), (80, 16));
        assert_eq!(c.get(21, 9), Some(CENTRE));
        assert_eq!(c.get(61, 5), Some(CENTRE));
        // Radius size / 2 × zoom = 8 pixels; angle 0 points along +x.
        assert_eq!(c.get(21 + 8, 9), Some(OUTLINE));
        assert_eq!(c.get(21 + 5, 9), Some(OUTLINE));
        // The kept grid pixel covers half an image pixel: one canvas pixel, tinted.
        let tinted = c.get(0, 0).expect("inside");
        assert!(tinted[2] > tinted[0], "{tinted:?}");
        assert_eq!(c.get(1, 0), Some([100, 100, 100]));
        assert_eq!(c.get(40, 12), Some([100, 100, 100]));
    }

    #[test]
    fn absurd_sizes_angles_and_scales_draw_quickly_and_do_not_overflow() {
        let gray = vec![0u8; 16 * 4];
        let kps = [
            kp(3.0, 1.0, f32::INFINITY, f32::NAN),
            kp(5.0, 2.0, 1e30, 1e30),
            kp(7.0, 2.0, f32::NAN, 45.0),
        ];
        let view = ImageView {
            gray: &gray,
            width: 16,
            height: 4,
            scale_x: 0.0,
            scale_y: f64::NAN,
            keypoints: &kps,
        };
        let kept = Kept {
            pixels: &[0, 5, usize::MAX],
            rows: 4,
            cols: 16,
        };
        let c = draw(&view, Some(&kept));
        assert_eq!(c.get(7, 3), Some(CENTRE));
    }
}
