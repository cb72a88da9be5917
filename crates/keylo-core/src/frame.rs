//! Organised LiDAR frames: the rows×cols grid every source produces.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use nalgebra::Point3;
use serde::{Deserialize, Serialize};

use crate::scan::{PixelPoints, ScanPoints};
use crate::{PointCloud, ShapeError};

/// One of the per-pixel channels of a [`LidarFrame`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Channel {
    /// Range in metres.
    Range,
    /// Return signal strength (photon counts), "intensity" in ROS drivers.
    Signal,
    /// Calibrated reflectivity.
    Reflectivity,
    /// Ambient near-infrared light.
    NearIr,
}

impl Channel {
    /// All channels, in storage order.
    pub const ALL: [Channel; 4] = [
        Channel::Range,
        Channel::Signal,
        Channel::Reflectivity,
        Channel::NearIr,
    ];

    /// The config name of the channel.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Range => "range",
            Channel::Signal => "signal",
            Channel::Reflectivity => "reflectivity",
            Channel::NearIr => "near-ir",
        }
    }
}

impl fmt::Display for Channel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Channel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Channel::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                format!("unknown channel `{s}`; allowed: range, signal, reflectivity, near-ir")
            })
    }
}

/// Intrinsics of a spinning multi-beam sensor, one entry per row (beam).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeamGeometry {
    /// Sensor model name, e.g. `OS0-128`.
    pub model: String,
    /// Elevation of each beam, degrees, row 0 first (top).
    pub altitude_deg: Vec<f64>,
    /// Azimuth offset of each beam, degrees.
    pub azimuth_deg: Vec<f64>,
    /// Distance from the lidar origin to the beam origin, millimetres.
    pub origin_to_beam_mm: f64,
    /// Columns of one full revolution.
    pub columns_per_frame: usize,
    /// Revolutions per second.
    pub frame_rate_hz: f64,
    /// Per row, how many columns earlier than its column's time the row's pixels fired: pixel
    /// `(r, c)` of a frame without `pixel_times` fired at `column_times[(c − lag[r]) mod
    /// cols]` (a destaggered Ouster image: each beam fires at its own column offset). Empty
    /// when every pixel fired at its column's time.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub column_lag_by_row: Vec<usize>,
}

impl BeamGeometry {
    /// Geometry of a sensor whose beams are not known (frames handed in as plain grids):
    /// no beam angles, `columns` per revolution, rate unknown (0).
    pub fn unknown(model: impl Into<String>, columns: usize) -> Self {
        Self {
            model: model.into(),
            altitude_deg: Vec::new(),
            azimuth_deg: Vec::new(),
            origin_to_beam_mm: 0.0,
            columns_per_frame: columns,
            frame_rate_hz: 0.0,
            column_lag_by_row: Vec::new(),
        }
    }
}

/// An organised frame: every channel is a row-major `rows × cols` grid.
///
/// Pixel `(r, c)` is at index `r * cols + c`. Invalid pixels (no return) have `valid = false`,
/// range 0 and point at the origin. `points` are in the sensor frame, metres.
#[derive(Debug, Clone, PartialEq)]
pub struct LidarFrame {
    /// Sequence number of the frame in its source.
    pub index: u64,
    /// Time of the first column, seconds.
    pub timestamp: f64,
    pub rows: usize,
    pub cols: usize,
    /// Firing time of every column, seconds (absolute, same clock as `timestamp`).
    pub column_times: Vec<f64>,
    /// Firing time of every pixel, seconds, when pixels of one column fired at different
    /// times (a destaggered Ouster image, a projected cloud with per-point times). `None`:
    /// every pixel has its column's time.
    pub pixel_times: Option<Vec<f64>>,
    /// Range per pixel, metres.
    pub range: Vec<f32>,
    /// Signal per pixel.
    pub signal: Vec<f32>,
    /// Reflectivity per pixel.
    pub reflectivity: Vec<f32>,
    /// Near-IR (ambient) per pixel.
    pub near_ir: Vec<f32>,
    /// 3-D point per pixel in the sensor frame.
    pub points: Vec<Point3<f32>>,
    /// Whether the pixel holds a return.
    pub valid: Vec<bool>,
    /// Beam intrinsics shared by all frames of a sequence.
    pub beams: Arc<BeamGeometry>,
    /// For frames of an unorganised source: every finite point of the scan in file order,
    /// with the pixel each falls into (the grids above show the nearest point of each pixel).
    /// `None` when the sensor delivered the grid itself (one point per pixel).
    pub scan: Option<Arc<ScanPoints>>,
}

impl LidarFrame {
    /// An all-invalid frame of the given size.
    pub fn empty(
        index: u64,
        timestamp: f64,
        rows: usize,
        cols: usize,
        beams: Arc<BeamGeometry>,
    ) -> Self {
        let n = rows * cols;
        Self {
            index,
            timestamp,
            rows,
            cols,
            column_times: vec![timestamp; cols],
            pixel_times: None,
            range: vec![0.0; n],
            signal: vec![0.0; n],
            reflectivity: vec![0.0; n],
            near_ir: vec![0.0; n],
            points: vec![Point3::origin(); n],
            valid: vec![false; n],
            beams,
            scan: None,
        }
    }

    /// The grid of one channel.
    pub fn channel(&self, channel: Channel) -> &[f32] {
        match channel {
            Channel::Range => &self.range,
            Channel::Signal => &self.signal,
            Channel::Reflectivity => &self.reflectivity,
            Channel::NearIr => &self.near_ir,
        }
    }

    /// Firing time of pixel `i` (row-major), seconds: from `pixel_times`, else from
    /// `column_times` and the beams' [`BeamGeometry::column_lag_by_row`].
    #[inline]
    pub fn pixel_time(&self, i: usize) -> f64 {
        match &self.pixel_times {
            Some(t) => t[i],
            None => {
                let c = i % self.cols;
                match self.column_lags() {
                    Some(lags) => {
                        let lag = lags[i / self.cols] % self.cols;
                        self.column_times[(c + self.cols - lag) % self.cols]
                    }
                    None => self.column_times[c],
                }
            }
        }
    }

    /// The beams' column lags, when they describe this frame (one per row, a full revolution
    /// of columns).
    #[inline]
    fn column_lags(&self) -> Option<&[usize]> {
        let lags = &self.beams.column_lag_by_row;
        (!lags.is_empty() && lags.len() == self.rows && self.beams.columns_per_frame == self.cols)
            .then_some(lags.as_slice())
    }

    /// Every pixel's firing time (row-major), when pixels of one column fired at different
    /// times: `pixel_times`, or the times the column lags give; `None` when every pixel has
    /// its column's time.
    pub fn pixel_times_or_lagged(&self) -> Option<std::borrow::Cow<'_, [f64]>> {
        if let Some(t) = &self.pixel_times {
            return Some(std::borrow::Cow::Borrowed(t));
        }
        self.column_lags()?;
        let n = self.rows * self.cols;
        Some(std::borrow::Cow::Owned(
            (0..n).map(|i| self.pixel_time(i)).collect(),
        ))
    }

    /// The time a pose of this frame refers to: `timestamp` plus the latest firing time of
    /// the frame's points (every scan point of an unorganised frame, else every valid finite
    /// pixel), i.e. the scan's end. It does not depend on which points a downsampler keeps,
    /// so a keypoint cloud's pose carries the same stamp as the raw cloud's. `timestamp` when
    /// the points have no times.
    pub fn end_stamp(&self) -> f64 {
        let latest = match &self.scan {
            Some(scan) => scan
                .times
                .as_ref()
                .and_then(|t| t.iter().copied().reduce(f64::max)),
            None => (0..self.rows * self.cols)
                .filter(|&i| self.has_point(i))
                .map(|i| self.pixel_time(i) - self.timestamp)
                .reduce(f64::max),
        };
        self.timestamp + latest.unwrap_or(0.0)
    }

    /// Whether pixel `i` (row-major) gives a point: valid, with finite coordinates.
    #[inline]
    fn has_point(&self, i: usize) -> bool {
        self.valid[i] && self.points[i].coords.iter().all(|v| v.is_finite())
    }

    /// Number of valid pixels.
    pub fn valid_count(&self) -> usize {
        self.valid.iter().filter(|v| **v).count()
    }

    /// Checks that every grid has `rows * cols` entries and `column_times` has `cols`.
    pub fn check_shape(&self) -> Result<(), ShapeError> {
        let n = self.rows * self.cols;
        let grids = [
            ("range", self.range.len()),
            ("signal", self.signal.len()),
            ("reflectivity", self.reflectivity.len()),
            ("near_ir", self.near_ir.len()),
            ("points", self.points.len()),
            ("valid", self.valid.len()),
        ];
        let pixel_times = self.pixel_times.as_ref().map(Vec::len);
        for (field, len) in grids
            .into_iter()
            .chain(pixel_times.map(|l| ("pixel_times", l)))
        {
            if len != n {
                return Err(ShapeError::Length {
                    field,
                    len,
                    what: "rows*cols",
                    expected: n,
                });
            }
        }
        if self.column_times.len() != self.cols {
            return Err(ShapeError::Length {
                field: "column_times",
                len: self.column_times.len(),
                what: "cols",
                expected: self.cols,
            });
        }
        match &self.scan {
            Some(scan) => scan.check(n),
            None => Ok(()),
        }
    }

    /// Every point of the frame as a cloud with per-point times and intensities: every
    /// point of the scan for an unorganised source, every valid pixel's point otherwise.
    pub fn to_cloud(&self) -> PointCloud {
        self.cloud(PixelPoints::All)
    }

    /// The whole frame as a cloud: every scan point ([`PixelPoints::All`]) or one point per
    /// valid pixel ([`PixelPoints::Nearest`]; the same for organised frames).
    pub fn cloud(&self, mode: PixelPoints) -> PointCloud {
        match (&self.scan, mode) {
            (Some(scan), PixelPoints::All) => PointCloud {
                timestamp: self.timestamp,
                points: scan.points.clone(),
                times: scan.times.clone(),
                intensities: Some(
                    scan.intensity
                        .clone()
                        .unwrap_or_else(|| vec![0.0; scan.len()]),
                ),
            },
            _ => self.cloud_of_pixels((0..self.rows * self.cols).filter(|&i| self.valid[i])),
        }
    }

    /// The points of the given pixels (row-major indices, ascending): with
    /// [`PixelPoints::All`] every scan point that falls into one of them, in file order;
    /// otherwise (and for organised frames) each valid pixel's own point.
    pub fn cloud_of_selected(&self, pixels: &[usize], mode: PixelPoints) -> PointCloud {
        match (&self.scan, mode) {
            (Some(scan), PixelPoints::All) => {
                let indices = scan.points_in(&self.pixel_mask(pixels));
                self.cloud_of_scan_points(scan, indices.into_iter())
            }
            _ => self.cloud_of_pixels(pixels.iter().copied()),
        }
    }

    /// How many points [`Self::cloud_of_selected`] returns for `pixels`, without building
    /// the cloud.
    pub fn count_selected(&self, pixels: &[usize], mode: PixelPoints) -> usize {
        match (&self.scan, mode) {
            (Some(scan), PixelPoints::All) => scan.count_in(&self.pixel_mask(pixels)),
            _ => pixels.iter().filter(|&&i| self.has_point(i)).count(),
        }
    }

    fn pixel_mask(&self, pixels: &[usize]) -> Vec<bool> {
        let mut mask = vec![false; self.rows * self.cols];
        for &p in pixels {
            if let Some(m) = mask.get_mut(p) {
                *m = true;
            }
        }
        mask
    }

    /// The cloud of the given scan points (indices into `scan`).
    fn cloud_of_scan_points(
        &self,
        scan: &ScanPoints,
        indices: impl Iterator<Item = usize> + Clone,
    ) -> PointCloud {
        let points = indices.clone().map(|i| scan.points[i]).collect();
        PointCloud {
            timestamp: self.timestamp,
            points,
            times: scan
                .times
                .as_ref()
                .map(|t| indices.clone().map(|i| t[i]).collect()),
            intensities: Some(match &scan.intensity {
                Some(v) => indices.map(|i| v[i]).collect(),
                None => indices.map(|_| 0.0).collect(),
            }),
        }
    }

    /// The cloud of the given pixel indices (invalid or non-finite pixels are skipped): one
    /// point per pixel.
    pub fn cloud_of_pixels(&self, pixels: impl Iterator<Item = usize>) -> PointCloud {
        let mut points = Vec::new();
        let mut times = Vec::new();
        let mut intensities = Vec::new();
        for i in pixels {
            if !self.has_point(i) {
                continue;
            }
            points.push(self.points[i].cast::<f64>());
            times.push(self.pixel_time(i) - self.timestamp);
            intensities.push(self.signal[i]);
        }
        PointCloud {
            timestamp: self.timestamp,
            points,
            times: Some(times),
            intensities: Some(intensities),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beams() -> Arc<BeamGeometry> {
        Arc::new(BeamGeometry {
            model: "test".into(),
            altitude_deg: vec![1.0, -1.0],
            azimuth_deg: vec![0.0, 0.0],
            origin_to_beam_mm: 0.0,
            columns_per_frame: 3,
            frame_rate_hz: 10.0,
            column_lag_by_row: Vec::new(),
        })
    }

    #[test]
    fn cloud_keeps_valid_finite_pixels_with_times() {
        let mut f = LidarFrame::empty(0, 10.0, 2, 3, beams());
        f.column_times = vec![10.0, 10.05, 10.1];
        f.valid[1] = true;
        f.points[1] = Point3::new(1.0, 0.0, 0.0);
        f.valid[4] = true;
        f.points[4] = Point3::new(f32::NAN, 0.0, 0.0);
        let c = f.to_cloud();
        assert_eq!(c.len(), 1);
        let t = c.times.as_ref().map(|t| t[0]).unwrap_or(f64::NAN);
        assert!((t - 0.05).abs() < 1e-9);
        assert!(f.check_shape().is_ok());
    }

    #[test]
    fn end_stamp_is_the_latest_valid_finite_point_whatever_is_kept() {
        let mut f = LidarFrame::empty(0, 10.0, 2, 3, beams());
        f.column_times = vec![10.0, 10.05, 10.1];
        assert_eq!(f.end_stamp(), 10.0, "no point: the frame's timestamp");
        for i in [0, 1, 3] {
            f.valid[i] = true;
            f.points[i] = Point3::new(1.0, 0.0, 0.0);
        }
        // Column 2 is invalid in row 0 and non-finite in row 1: not the end.
        f.valid[5] = true;
        f.points[5] = Point3::new(f32::NAN, 0.0, 0.0);
        assert_eq!(f.end_stamp(), 10.0 + (10.05 - 10.0));
        // The same as the whole cloud's latest time, and as a pose of a cloud of one early
        // pixel would be stamped.
        let whole = f.to_cloud();
        let latest = whole
            .times
            .as_ref()
            .and_then(|t| t.iter().copied().reduce(f64::max));
        assert_eq!(Some(f.end_stamp()), latest.map(|t| whole.timestamp + t));
        f.pixel_times = Some(vec![10.0, 10.02, 10.1, 10.07, 10.09, 10.1]);
        assert_eq!(f.end_stamp(), 10.0 + (10.07 - 10.0));
        f.scan = Some(Arc::new(ScanPoints {
            points: vec![Point3::new(1.0, 0.0, 0.0); 2],
            times: Some(vec![0.01, 0.093]),
            intensity: None,
            ring: None,
            source_index: vec![0, 1],
            pixel: vec![0, 1],
            pixel_to_point: vec![0, 1, ScanPoints::NONE, ScanPoints::NONE, 1, 1],
        }));
        assert_eq!(
            f.end_stamp(),
            10.093,
            "an unorganised frame: its scan's times"
        );
    }

    /// Without `pixel_times`, the beams' column lags give each row's pixel the time of the
    /// column it was fired in; lags that do not describe the frame are not used.
    #[test]
    fn column_lags_give_each_rows_pixel_times() {
        let mut beams = (*beams()).clone();
        beams.column_lag_by_row = vec![0, 2];
        let mut f = LidarFrame::empty(0, 10.0, 2, 3, Arc::new(beams.clone()));
        f.column_times = vec![10.0, 10.05, 10.1];
        let times: Vec<f64> = (0..6).map(|i| f.pixel_time(i)).collect();
        // Row 1 fired two columns earlier: column c at column (c − 2) mod 3's time.
        assert_eq!(times, [10.0, 10.05, 10.1, 10.05, 10.1, 10.0]);
        assert_eq!(f.pixel_times_or_lagged().as_deref(), Some(&times[..]));
        // Stored times win; without lags every pixel has its column's time.
        f.pixel_times = Some(vec![1.0; 6]);
        assert_eq!(f.pixel_time(4), 1.0);
        f.pixel_times = None;
        beams.column_lag_by_row = vec![0];
        f.beams = Arc::new(beams);
        assert_eq!(f.pixel_time(4), 10.05);
        assert!(f.pixel_times_or_lagged().is_none());
    }

    #[test]
    fn shape_errors_name_the_grid() {
        let mut f = LidarFrame::empty(0, 0.0, 2, 3, beams());
        f.signal.pop();
        let err = f.check_shape().err().unwrap();
        assert_eq!(
            err,
            ShapeError::Length {
                field: "signal",
                len: 5,
                what: "rows*cols",
                expected: 6
            }
        );
        assert_eq!(
            err.to_string(),
            "signal has 5 entries, expected rows*cols = 6"
        );
    }

    #[test]
    fn channel_names_round_trip() {
        for c in Channel::ALL {
            assert_eq!(c.name().parse::<Channel>(), Ok(c));
        }
        assert!("rgb".parse::<Channel>().is_err());
    }
}
