//! The robustness tests' image transforms and the homographies that map keypoints of the
//! original image into the transformed one: rotation on an enlarged canvas, scaling and
//! Gaussian blur, done with OpenCV as the authors' code does.

use keylo_core::Image;
use keylo_features::cv::{mat_bytes, to_mat};
use keylo_features::FeaturesError;
use opencv::core::{Mat, Size, BORDER_CONSTANT, BORDER_DEFAULT};
use opencv::prelude::*;

use crate::{Definitions, KpEvalError, ScalingHomography};

/// A 2-D homography, row-major 3×3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Homography(pub [f64; 9]);

impl Homography {
    /// The identity.
    pub const IDENTITY: Self = Self([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);

    /// `(x, y)` mapped.
    pub fn map(&self, x: f64, y: f64) -> (f64, f64) {
        let h = &self.0;
        let w = h[6] * x + h[7] * y + h[8];
        (
            (h[0] * x + h[1] * y + h[2]) / w,
            (h[3] * x + h[4] * y + h[5]) / w,
        )
    }
}

/// A transformed image and the homography from original to transformed pixels.
#[derive(Debug, Clone)]
pub struct Transformed {
    pub image: Image,
    pub h: Homography,
}

fn cv(op: &'static str) -> impl FnOnce(opencv::Error) -> KpEvalError {
    move |e| KpEvalError::Features(FeaturesError::opencv(op, e))
}

fn image_from(mat: &Mat, like: &Image) -> Result<Image, KpEvalError> {
    let width = usize::try_from(mat.cols()).unwrap_or(0);
    let height = usize::try_from(mat.rows()).unwrap_or(0);
    let source = like
        .sources
        .first()
        .copied()
        .unwrap_or(keylo_core::Channel::Signal);
    let mut out = Image::new_gray(width, height, source);
    out.sources = like.sources.clone();
    out.data = mat_bytes(mat)?;
    Ok(out)
}

fn size(w: f64, h: f64) -> Size {
    Size::new(w.round().max(1.0) as i32, h.round().max(1.0) as i32)
}

/// `image` rotated by `degrees` (counter-clockwise, as OpenCV's `getRotationMatrix2D`) about
/// its centre, on a canvas enlarged to the rotated bounding box (linear interpolation, black
/// outside). The box is OpenCV's `RotatedRect(…).boundingRect2f()`, computed in `f32` as
/// OpenCV does: the authors shift the rotation by half its growth (a fraction of a pixel
/// that moves every sample of the rotated image) and size the canvas by rounding it.
pub fn rotate(image: &Image, degrees: f64, defs: Definitions) -> Result<Transformed, KpEvalError> {
    let (w, h) = (image.width as f64, image.height as f64);
    let (cx, cy) = (w / 2.0, h / 2.0);
    let (sin, cos) = degrees.to_radians().sin_cos();
    let (box_w, box_h) = match defs {
        Definitions::Program => bounding_box_f32(image.width as f32, image.height as f32, degrees),
        // `int(h·|sin| + w·|cos|)`, `int(h·|cos| + w·|sin|)` in f64, as the script computes.
        Definitions::SuperPointScript => (
            (h * sin.abs() + w * cos.abs()).trunc() as f32,
            (h * cos.abs() + w * sin.abs()).trunc() as f32,
        ),
    };
    // getRotationMatrix2D(centre, degrees, 1), then shifted by half the box's growth.
    let m = [
        cos,
        sin,
        (1.0 - cos) * cx - sin * cy + (f64::from(box_w) - w) / 2.0,
        -sin,
        cos,
        sin * cx + (1.0 - cos) * cy + (f64::from(box_h) - h) / 2.0,
    ];
    let affine = Mat::from_slice_2d(&[&m[0..3], &m[3..6]]).map_err(cv("Mat::from_slice_2d"))?;
    let mut dst = Mat::default();
    opencv::imgproc::warp_affine(
        &to_mat(image)?,
        &mut dst,
        &affine,
        size(f64::from(box_w), f64::from(box_h)),
        opencv::imgproc::INTER_LINEAR,
        BORDER_CONSTANT,
        opencv::core::Scalar::all(0.0),
    )
    .map_err(cv("warpAffine"))?;
    Ok(Transformed {
        image: image_from(&dst, image)?,
        h: Homography([m[0], m[1], m[2], m[3], m[4], m[5], 0.0, 0.0, 1.0]),
    })
}

/// Width and height of the bounding box of a `w × h` rectangle rotated by `degrees`, as
/// OpenCV's `RotatedRect::boundingRect2f` computes them (corner points in `f32`).
fn bounding_box_f32(w: f32, h: f32, degrees: f64) -> (f32, f32) {
    let angle = degrees * std::f64::consts::PI / 180.0;
    let (b, a) = (angle.cos() as f32 * 0.5, angle.sin() as f32 * 0.5);
    let (x0, y0) = (-a * h - b * w, b * h - a * w);
    let (x1, y1) = (a * h - b * w, -b * h - a * w);
    // The other two corners are these mirrored through the centre (0, 0).
    let span = |v: [f32; 4]| {
        let (lo, hi) = v
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        hi - lo
    };
    (span([x0, x1, -x0, -x1]), span([y0, y1, -y0, -y1]))
}

/// `image` resized by `factor` (linear), with the homography of `mode`.
pub fn scale(
    image: &Image,
    factor: f64,
    mode: ScalingHomography,
) -> Result<Transformed, KpEvalError> {
    let mut dst = Mat::default();
    opencv::imgproc::resize(
        &to_mat(image)?,
        &mut dst,
        Size::new(0, 0),
        factor,
        factor,
        opencv::imgproc::INTER_LINEAR,
    )
    .map_err(cv("resize"))?;
    Ok(Transformed {
        image: image_from(&dst, image)?,
        h: scaling_homography(mode, factor, image.width, image.height),
    })
}

/// The homography of a `factor` scaling of a `cols × rows` image.
pub fn scaling_homography(
    mode: ScalingHomography,
    factor: f64,
    cols: usize,
    rows: usize,
) -> Homography {
    let (tx, ty) = match mode {
        ScalingHomography::Paper => (
            (factor - 1.0) * cols as f64 / 2.0,
            (factor - 1.0) * rows as f64 / 2.0,
        ),
        ScalingHomography::Corrected => ((factor - 1.0) / 2.0, (factor - 1.0) / 2.0),
        ScalingHomography::Plain => (0.0, 0.0),
    };
    Homography([factor, 0.0, tx, 0.0, factor, ty, 0.0, 0.0, 1.0])
}

/// `image` blurred with a `kernel × kernel` Gaussian (`sigma` 0: from the kernel size);
/// the homography is the identity.
pub fn blur(image: &Image, kernel: usize, sigma: f64) -> Result<Transformed, KpEvalError> {
    let k =
        i32::try_from(kernel).map_err(|_| KpEvalError::Input(format!("blur kernel {kernel}")))?;
    let mut dst = Mat::default();
    opencv::imgproc::gaussian_blur(
        &to_mat(image)?,
        &mut dst,
        Size::new(k, k),
        sigma,
        sigma,
        BORDER_DEFAULT,
    )
    .map_err(cv("GaussianBlur"))?;
    Ok(Transformed {
        image: image_from(&dst, image)?,
        h: Homography::IDENTITY,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;
    use keylo_core::Channel;

    /// A black image with one bright 3×3 square centred on (x, y).
    fn dot(w: usize, h: usize, x: usize, y: usize) -> Image {
        let mut img = Image::new_gray(w, h, Channel::Signal);
        for yy in y - 1..=y + 1 {
            for xx in x - 1..=x + 1 {
                img.data[yy * w + xx] = 255;
            }
        }
        img
    }

    /// Intensity-weighted centroid of an image.
    fn centroid(img: &Image) -> (f64, f64) {
        let (mut sx, mut sy, mut s) = (0.0, 0.0, 0.0);
        for y in 0..img.height {
            for x in 0..img.width {
                let v = f64::from(img.data[y * img.stride + x]);
                sx += v * x as f64;
                sy += v * y as f64;
                s += v;
            }
        }
        (sx / s, sy / s)
    }

    #[test]
    fn rotation_maps_a_dot_where_its_homography_says_on_an_enlarged_canvas() {
        let img = dot(100, 20, 80, 5);
        let t = rotate(&img, 45.0, Definitions::Program).unwrap();
        // 100·cos45 + 20·sin45 = 84.85, rounded as OpenCV turns the box into a size
        assert_eq!((t.image.width, t.image.height), (85, 85)); // OpenCV rounds the box
        let (x, y) = t.h.map(80.0, 5.0);
        let (cx, cy) = centroid(&t.image);
        assert_abs_diff_eq!(x, cx, epsilon = 0.6);
        assert_abs_diff_eq!(y, cy, epsilon = 0.6);
        // The SuperPoint script truncates the canvas and centres the image on it.
        let t = rotate(&img, 45.0, Definitions::SuperPointScript).unwrap();
        assert_eq!((t.image.width, t.image.height), (84, 84));
        let (x, y) = t.h.map(80.0, 5.0);
        let (cx, cy) = centroid(&t.image);
        assert_abs_diff_eq!(x, cx, epsilon = 0.6);
        assert_abs_diff_eq!(y, cy, epsilon = 0.6);
        let (mx, my) = t.h.map(50.0, 10.0);
        assert_abs_diff_eq!(mx, 42.0, epsilon = 1e-9);
        assert_abs_diff_eq!(my, 42.0, epsilon = 1e-9);
    }

    #[test]
    fn the_corrected_scaling_homography_is_what_resize_does_and_the_papers_is_not() {
        let img = dot(64, 16, 40, 6);
        let t = scale(&img, 2.0, ScalingHomography::Corrected).unwrap();
        assert_eq!((t.image.width, t.image.height), (128, 32));
        let (cx, cy) = centroid(&t.image);
        let (x, y) = t.h.map(40.0, 6.0);
        assert_abs_diff_eq!(x, cx, epsilon = 0.3);
        assert_abs_diff_eq!(y, cy, epsilon = 0.3);
        let paper = scaling_homography(ScalingHomography::Paper, 2.0, 64, 16);
        let (px, py) = paper.map(40.0, 6.0);
        assert_abs_diff_eq!(px, 80.0 + 32.0);
        assert_abs_diff_eq!(py, 12.0 + 8.0);
        let plain = scaling_homography(ScalingHomography::Plain, 2.0, 64, 16);
        assert_eq!(plain.map(40.0, 6.0), (80.0, 12.0));
    }

    #[test]
    fn blur_keeps_the_size_and_spreads_the_dot() {
        let img = dot(32, 16, 10, 8);
        let t = blur(&img, 5, 0.0).unwrap();
        assert_eq!((t.image.width, t.image.height), (32, 16));
        assert!(t.image.data[8 * 32 + 10] < 255);
        assert!(t.image.data[8 * 32 + 12] > 0);
        assert_eq!(t.h, Homography::IDENTITY);
    }
}
