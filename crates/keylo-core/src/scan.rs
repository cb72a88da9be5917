//! The points of an unorganised scan (KITTI `.bin`, PLY/PCD, an unorganised `PointCloud2`):
//! every finite point in file order, and the pixel of the frame's image grid each falls into.
//!
//! The grid of such a frame is an *index* over these points, not a filter: a pixel may hold
//! several points, and the images show the nearest of them ([`ScanPoints::pixel_to_point`]).
//! Organised sources (Ouster, the simulator, organised `PointCloud2`) deliver one point per
//! pixel and carry no `ScanPoints`.

use crate::ShapeError;
use nalgebra::Point3;
use serde::{Deserialize, Serialize};

/// Every finite point of an unorganised scan, in file order, with its grid pixel.
///
/// All per-point vectors have one entry per point; `pixel_to_point` has one per grid pixel.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScanPoints {
    /// Points in the sensor frame, metres; every coordinate is finite. Double precision:
    /// a reader may correct the file's values (KITTI's vertical-angle correction) and the
    /// registrar gets the corrected values unrounded.
    pub points: Vec<Point3<f64>>,
    /// Firing time of every point relative to the frame's `timestamp`, seconds: from the
    /// file, or spread over one revolution by azimuth when the source knows its rate;
    /// `None` when neither is known.
    pub times: Option<Vec<f64>>,
    /// Intensity (signal) of every point, when the file has one.
    pub intensity: Option<Vec<f32>>,
    /// Beam (ring) of every point, when the file has one.
    pub ring: Option<Vec<u16>>,
    /// Index of every point in its file or message (non-finite points are skipped, so the
    /// indices can jump).
    pub source_index: Vec<u32>,
    /// Row-major grid pixel of every point, or [`ScanPoints::NONE`] when the point lies
    /// outside the grid (beyond the vertical field of view, or at the origin).
    pub pixel: Vec<u32>,
    /// Per grid pixel, the point whose values the images show: the nearest point of the
    /// pixel (the first in file order among equally near ones), or [`ScanPoints::NONE`].
    pub pixel_to_point: Vec<u32>,
}

impl ScanPoints {
    /// Marks an empty pixel or a point outside the grid.
    pub const NONE: u32 = u32::MAX;

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True when the scan holds no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Checks that every per-point field has one entry per point, `pixel_to_point` one per
    /// of the `pixels` grid pixels, and every index is in range; the error names the field.
    pub fn check(&self, pixels: usize) -> Result<(), ShapeError> {
        let n = self.points.len();
        let lens = [
            ("scan.times", self.times.as_ref().map(Vec::len)),
            ("scan.intensity", self.intensity.as_ref().map(Vec::len)),
            ("scan.ring", self.ring.as_ref().map(Vec::len)),
            ("scan.source_index", Some(self.source_index.len())),
            ("scan.pixel", Some(self.pixel.len())),
        ];
        for (field, len) in lens {
            if let Some(len) = len.filter(|&l| l != n) {
                return Err(ShapeError::Length {
                    field,
                    len,
                    what: "points",
                    expected: n,
                });
            }
        }
        if self.pixel_to_point.len() != pixels {
            return Err(ShapeError::Length {
                field: "scan.pixel_to_point",
                len: self.pixel_to_point.len(),
                what: "rows*cols",
                expected: pixels,
            });
        }
        let outside = |v: &u32, limit: usize| *v != Self::NONE && *v as usize >= limit;
        if self.pixel.iter().any(|p| outside(p, pixels)) {
            return Err(ShapeError::IndexOutOfRange {
                field: "scan.pixel",
                what: "rows*cols",
                limit: pixels,
            });
        }
        if self.pixel_to_point.iter().any(|p| outside(p, n)) {
            return Err(ShapeError::IndexOutOfRange {
                field: "scan.pixel_to_point",
                what: "points",
                limit: n,
            });
        }
        if self
            .points
            .iter()
            .any(|p| !p.coords.iter().all(|v| v.is_finite()))
        {
            return Err(ShapeError::NonFinitePoint);
        }
        Ok(())
    }

    /// Indices of the points whose pixel is set in `mask` (row-major, one flag per pixel),
    /// in file order.
    pub fn points_in(&self, mask: &[bool]) -> Vec<usize> {
        self.iter_in(mask).collect()
    }

    /// How many points [`Self::points_in`] gives for `mask`, without collecting them.
    pub fn count_in(&self, mask: &[bool]) -> usize {
        self.iter_in(mask).count()
    }

    fn iter_in<'a>(&'a self, mask: &'a [bool]) -> impl Iterator<Item = usize> + 'a {
        self.pixel
            .iter()
            .enumerate()
            .filter(|(_, &p)| p != Self::NONE && mask.get(p as usize).copied().unwrap_or(false))
            .map(|(i, _)| i)
    }

    /// How many pixels hold at least one point, and how many points share a pixel with a
    /// nearer one (points in a pixel beyond its first): the grid's collisions.
    pub fn occupancy(&self) -> GridOccupancy {
        let mut counts = vec![0u32; self.pixel_to_point.len()];
        let mut outside = 0;
        for &p in &self.pixel {
            match counts.get_mut(p as usize) {
                Some(c) => *c += 1,
                None => outside += 1,
            }
        }
        let occupied = counts.iter().filter(|&&c| c > 0).count();
        let max = counts.iter().copied().max().unwrap_or(0) as usize;
        GridOccupancy {
            points: self.len(),
            outside,
            occupied_pixels: occupied,
            sharing: self.len() - outside - occupied,
            max_per_pixel: max,
        }
    }
}

/// How the points of a scan fill its grid ([`ScanPoints::occupancy`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GridOccupancy {
    /// Points in the scan.
    pub points: usize,
    /// Points that fall into no pixel (outside the vertical field of view, at the origin).
    pub outside: usize,
    /// Pixels holding at least one point.
    pub occupied_pixels: usize,
    /// Points that are not the first of their pixel: an image shows only one point per
    /// pixel, so these are the points a one-point-per-pixel grid would drop.
    pub sharing: usize,
    /// Most points in one pixel.
    pub max_per_pixel: usize,
}

/// Which points of a selected pixel a downsampler keeps when an unorganised scan puts
/// several points into one pixel (`pixel_points = "..."` in its config). Organised frames
/// hold one point per pixel, so there both are the same.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum PixelPoints {
    /// Every point of the scan whose pixel is selected (every point, for a whole frame).
    #[default]
    All,
    /// One point per pixel: the nearest, the one the images show (what an organised sensor
    /// such as the paper's Ouster delivers).
    Nearest,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scan() -> ScanPoints {
        ScanPoints {
            points: vec![Point3::new(1.0, 0.0, 0.0); 4],
            source_index: vec![0, 1, 3, 4],
            pixel: vec![0, 0, ScanPoints::NONE, 2],
            pixel_to_point: vec![1, ScanPoints::NONE, 3],
            ..ScanPoints::default()
        }
    }

    #[test]
    fn points_in_a_mask_come_in_file_order() {
        let s = scan();
        assert_eq!(s.points_in(&[true, false, true]), vec![0, 1, 3]);
        assert_eq!(s.count_in(&[true, false, true]), 3);
        assert_eq!(s.points_in(&[false, true, false]), Vec::<usize>::new());
        assert!(s.check(3).is_ok());
    }

    #[test]
    fn occupancy_counts_shared_pixels_and_outsiders() {
        let o = scan().occupancy();
        assert_eq!(
            o,
            GridOccupancy {
                points: 4,
                outside: 1,
                occupied_pixels: 2,
                sharing: 1,
                max_per_pixel: 2
            }
        );
    }

    #[test]
    fn check_names_the_bad_field() {
        let mut s = scan();
        assert!(s
            .check(4)
            .unwrap_err()
            .to_string()
            .contains("pixel_to_point"));
        s.pixel[0] = 7;
        assert!(s.check(3).unwrap_err().to_string().contains("scan.pixel"));
        let mut s = scan();
        s.times = Some(vec![0.0]);
        assert!(s.check(3).unwrap_err().to_string().contains("scan.times"));
        let mut s = scan();
        s.points[2].x = f64::NAN;
        assert!(s.check(3).unwrap_err().to_string().contains("non-finite"));
    }
}
