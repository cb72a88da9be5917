//! Keypoints with the 3-D point under each: the side input of registrars that match
//! keypoints between frames (see [`crate::Registrar::register_with_keypoints`]).

use nalgebra::Point3;

use crate::pixel_math::{clip_rows, cover, window, wrap_col};
use crate::{ChannelFeatures, DescriptorData, Descriptors, FrameFeatures, LidarFrame};

/// The described keypoints of one image whose pixel holds a return.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageKeypoints {
    /// The image's name ([`crate::Image::name`]); keypoints match only within one image.
    pub image: String,
    /// Sensor-frame point under each keypoint, metres.
    pub points: Vec<Point3<f64>>,
    /// Time of each point relative to the frame's timestamp, seconds.
    pub times: Vec<f64>,
    /// Row `i` describes `points[i]`.
    pub descriptors: Descriptors,
}

/// Every image's [`ImageKeypoints`] of one frame.
///
/// ```
/// use keylo_core::FrameKeypoints;
/// assert_eq!(FrameKeypoints::default().len(), 0);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameKeypoints {
    pub per_image: Vec<ImageKeypoints>,
}

impl FrameKeypoints {
    /// The keypoints of `features` that have descriptors, each mapped to the frame pixel
    /// under it (the covered pixel of the keypoint's image pixel nearest to its centre that
    /// holds a return, by the downsampler's index math); keypoints over no return are left out.
    /// The point is interpolated bilinearly between the four grid pixels around the keypoint
    /// when all hold returns within 5 % of one another's range (a smooth surface), so that it
    /// moves continuously with the keypoint; at depth edges it is the pixel's own point.
    pub fn from_features(frame: &LidarFrame, features: &FrameFeatures) -> Self {
        let per_image = features
            .per_image
            .iter()
            .filter_map(|c| image_keypoints(frame, c))
            .collect();
        Self { per_image }
    }

    /// Keypoints over all images.
    pub fn len(&self) -> usize {
        self.per_image.iter().map(|i| i.points.len()).sum()
    }

    /// True when no image has a keypoint.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn image_keypoints(frame: &LidarFrame, c: &ChannelFeatures) -> Option<ImageKeypoints> {
    let descriptors = c.descriptors.as_ref()?;
    if descriptors.rows != c.keypoints.len() || !well_formed(descriptors) {
        return None;
    }
    let (mut points, mut times, mut rows) = (Vec::new(), Vec::new(), Vec::new());
    for (i, kp) in c.keypoints.iter().enumerate() {
        let Some((pixel, point)) = point_under(frame, c, kp) else {
            continue;
        };
        points.push(point);
        times.push(frame.pixel_time(pixel) - frame.timestamp);
        rows.push(i);
    }
    Some(ImageKeypoints {
        image: c.image.name(),
        points,
        times,
        descriptors: descriptor_rows(descriptors, &rows),
    })
}

/// The sensor-frame point under every keypoint of `c`, aligned with `c.keypoints` (`None`
/// over no return), placed as [`FrameKeypoints::from_features`] places them; for keypoints
/// with or without descriptors.
pub fn keypoint_points(frame: &LidarFrame, c: &ChannelFeatures) -> Vec<Option<Point3<f64>>> {
    c.keypoints
        .iter()
        .map(|kp| point_under(frame, c, kp).map(|(_, p)| p))
        .collect()
}

/// The frame pixel under keypoint `kp` of `c` and the point placed there.
fn point_under(
    frame: &LidarFrame,
    c: &ChannelFeatures,
    kp: &crate::Keypoint,
) -> Option<(usize, Point3<f64>)> {
    let (pixel, gx, gy) = pixel_under(frame, c, kp.x, kp.y)?;
    let point = bilinear(frame, gx, gy).unwrap_or_else(|| frame.points[pixel].cast::<f64>());
    Some((pixel, point))
}

/// Whether pixel `i` holds a finite return.
fn usable(frame: &LidarFrame, i: usize) -> bool {
    frame.valid[i] && frame.range[i] > 0.0 && frame.points[i].coords.iter().all(|v| v.is_finite())
}

/// The point at grid position `(gx, gy)` (pixel-centre coordinates) interpolated between the
/// four pixels around it, when all hold returns of nearly equal range.
fn bilinear(frame: &LidarFrame, gx: f64, gy: f64) -> Option<Point3<f64>> {
    let (x0, y0) = (gx.floor(), gy.floor());
    let (fx, fy) = (gx - x0, gy - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    if y0 < 0 || y0 + 1 >= frame.rows as i64 {
        return None;
    }
    let mut sum = nalgebra::Vector3::zeros();
    let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
    for (dy, wy) in [(0, 1.0 - fy), (1, fy)] {
        for (dx, wx) in [(0, 1.0 - fx), (1, fx)] {
            let i = (y0 + dy) as usize * frame.cols + wrap_col(x0 + dx, frame.cols);
            if !usable(frame, i) {
                return None;
            }
            lo = lo.min(frame.range[i]);
            hi = hi.max(frame.range[i]);
            sum += frame.points[i].coords.cast::<f64>() * (wx * wy);
        }
    }
    (hi <= 1.05 * lo).then_some(Point3::from(sum))
}

/// The frame pixel under image point `(x, y)`: of the grid pixels its image pixel covers,
/// the one nearest to the point that holds a finite return; with the point's grid position.
fn pixel_under(
    frame: &LidarFrame,
    c: &ChannelFeatures,
    x: f32,
    y: f32,
) -> Option<(usize, f64, f64)> {
    let (w, h) = (c.image.width, c.image.height);
    let inside = x.is_finite() && y.is_finite() && x > -1.0 && y > -1.0;
    if !inside || x >= w as f32 || y >= h as f32 {
        return None;
    }
    let (cols, rows) = (frame.cols, frame.rows);
    let (xi, _) = window(x, 1);
    let (yi, _) = window(y, 1);
    let (c0, c1) = cover(xi, xi, cols, w);
    let (r0, r1) = cover(yi, yi, rows, h);
    let (r0, r1) = clip_rows(r0, r1, rows)?;
    // The keypoint's position on the grid, in pixel-centre coordinates.
    let gx = (f64::from(x) + 0.5) * cols as f64 / w.max(1) as f64 - 0.5;
    let gy = (f64::from(y) + 0.5) * rows as f64 / h.max(1) as f64 - 0.5;
    let mut best: Option<(f64, usize)> = None;
    for r in r0..=r1 {
        for col in c0..=c1 {
            let i = r * cols + wrap_col(col, cols);
            let ok = usable(frame, i);
            let d2 = (col as f64 - gx).powi(2) + (r as f64 - gy).powi(2);
            if ok && best.is_none_or(|(b, _)| d2 < b) {
                best = Some((d2, i));
            }
        }
    }
    best.map(|(_, i)| (i, gx, gy))
}

/// Whether `d` holds exactly `rows × dim` elements.
pub fn well_formed(d: &Descriptors) -> bool {
    let n = match &d.data {
        DescriptorData::Binary(v) => v.len(),
        DescriptorData::Float(v) => v.len(),
    };
    d.rows.checked_mul(d.dim) == Some(n)
}

/// The rows `rows` (each `< d.rows`) of a [`well_formed`] `d`.
fn descriptor_rows(d: &Descriptors, rows: &[usize]) -> Descriptors {
    let data = match &d.data {
        DescriptorData::Binary(v) => DescriptorData::Binary(
            rows.iter()
                .flat_map(|&r| v[r * d.dim..(r + 1) * d.dim].iter().copied())
                .collect(),
        ),
        DescriptorData::Float(v) => DescriptorData::Float(
            rows.iter()
                .flat_map(|&r| v[r * d.dim..(r + 1) * d.dim].iter().copied())
                .collect(),
        ),
    };
    Descriptors {
        rows: rows.len(),
        dim: d.dim,
        data,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BeamGeometry, Channel, Image, Keypoint};
    use std::sync::Arc;

    fn frame() -> LidarFrame {
        let beams = Arc::new(BeamGeometry::unknown("test", 8));
        let mut f = LidarFrame::empty(0, 1.0, 4, 8, beams);
        for i in 0..32 {
            f.points[i] = Point3::new(i as f32, 1.0, 2.0);
            f.range[i] = 1.0;
            f.valid[i] = true;
        }
        f.valid[2 * 8 + 4] = false;
        f
    }

    #[test]
    fn maps_keypoints_of_a_halved_image_to_the_nearest_valid_pixel() {
        let f = frame();
        let mut image = Image::new_gray(4, 2, Channel::Signal);
        (image.scale_x, image.scale_y) = (2.0, 2.0);
        let kp = |x: f32, y: f32| Keypoint {
            x,
            y,
            ..Keypoint::default()
        };
        let c = ChannelFeatures {
            image,
            // (1.2, 1.0) covers rows 2..=3, cols 2..=3; grid centre (2.9, 2.5) → (2, 3) or (3, 3).
            keypoints: vec![kp(1.2, 1.0), kp(2.0, 1.0), kp(9.0, 0.0)],
            descriptors: Some(Descriptors {
                rows: 3,
                dim: 1,
                data: DescriptorData::Binary(vec![10, 20, 30]),
            }),
        };
        let features = FrameFeatures { per_image: vec![c] };
        let k = FrameKeypoints::from_features(&f, &features);
        assert_eq!(k.len(), 2);
        let img = &k.per_image[0];
        assert_eq!(img.image, "signal");
        // Grid position (2.9, 2.5): all four pixels around it hold returns of equal range, so
        // the point is interpolated: x = row·8 + col at (2.5, 2.9) = 22.9.
        assert!((img.points[0].x - 22.9).abs() < 1e-5, "{}", img.points[0]);
        // (2.0, 1.0): cols 4..=5, rows 2..=3, centre (4.5, 2.5); (2, 4) has no return, so no
        // interpolation: the nearest pixel with a return, (2, 5).
        assert_eq!(img.points[1].x, 21.0);
        assert_eq!(img.descriptors.data, DescriptorData::Binary(vec![10, 20]));
        // The same points per keypoint, descriptors or not, `None` off the image.
        let per_keypoint = keypoint_points(&f, &features.per_image[0]);
        assert_eq!(per_keypoint.len(), 3);
        assert_eq!(per_keypoint[0], Some(img.points[0]));
        assert_eq!(per_keypoint[1], Some(img.points[1]));
        assert_eq!(per_keypoint[2], None);
    }
}
