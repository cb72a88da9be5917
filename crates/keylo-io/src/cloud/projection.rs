//! Spherical projection of unorganised clouds onto a `rows × cols` grid.
//!
//! The column is the azimuth, clockwise seen from above with column 0 on the +x axis (the
//! layout of Ouster's destaggered images). The row is the point's beam: its ring index when
//! the cloud has one, else its elevation binned against a beam table or an even split of the
//! vertical field of view. The frame carries every finite point of the cloud in file order
//! ([`ScanPoints`], with each point's pixel); when several points fall into one pixel, the
//! image grids show the nearest (the first in file order among equally near ones).

use std::sync::Arc;

use super::azimuth::azimuth_column;
pub use super::projection_config::{Grid, ProjectionConfig, RingOrder, RowSource, Sensor};
use super::records::{PointFields, PointRecord};
use super::rows::RowLookup;
use super::{organised::column_times, CloudError, RawCloud, VerticalAngleCorrection};
use keylo_core::{BeamGeometry, LidarFrame, ScanPoints};
use nalgebra::Point3;
use rayon::prelude::*;

/// Projects the clouds of one sequence (the ring order, once decided, holds for all).
#[derive(Debug, Clone)]
pub struct Projector {
    grid: Grid,
    lookup: RowLookup,
    beams: Arc<BeamGeometry>,
    top_first: Option<bool>,
    correction: Option<VerticalAngleCorrection>,
    /// False when no stage reads the grid: frames then carry only their points.
    grid_needed: bool,
}

impl Projector {
    /// A projector for a resolved grid ([`ProjectionConfig::resolve`]).
    pub fn new(grid: Grid) -> Self {
        let rows = grid.rows;
        let beams = Arc::new(BeamGeometry {
            model: grid.model.clone(),
            altitude_deg: grid.altitudes_deg.clone(),
            azimuth_deg: vec![0.0; rows],
            origin_to_beam_mm: 0.0,
            columns_per_frame: grid.cols,
            frame_rate_hz: grid.frame_rate_hz,
            column_lag_by_row: Vec::new(),
        });
        let top_first = match grid.ring_order {
            RingOrder::Auto => None,
            RingOrder::TopFirst => Some(true),
            RingOrder::BottomFirst => Some(false),
        };
        Self {
            lookup: RowLookup::new(grid.altitudes_deg.clone()),
            grid,
            beams,
            top_first,
            correction: None,
            grid_needed: true,
        }
    }

    /// Whether frames get their image grid; without it a frame is `0 × 0` and carries only
    /// its points (every finite one, with times and intensities), which costs a fraction of
    /// the projection.
    pub fn set_grid_needed(&mut self, needed: bool) {
        self.grid_needed = needed;
    }

    /// Whether frames get their image grid ([`Projector::set_grid_needed`]).
    pub fn grid_needed(&self) -> bool {
        self.grid_needed
    }

    /// The projector of `config` for a source whose `auto` sensor is `source_default`.
    pub fn from_config(
        config: &ProjectionConfig,
        source_default: Sensor,
    ) -> Result<Self, CloudError> {
        config.resolve(source_default).map(Self::new)
    }

    /// Applies `correction` to every point as it is read (before its pixel is found).
    pub fn with_correction(mut self, correction: Option<VerticalAngleCorrection>) -> Self {
        self.correction = correction;
        self
    }

    /// The grid the clouds are projected onto.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The beam geometry every projected frame carries.
    pub fn beams(&self) -> &Arc<BeamGeometry> {
        &self.beams
    }

    /// The frame of `cloud`; the error says which field is inconsistent.
    pub fn project(&mut self, cloud: &RawCloud, index: u64) -> Result<LidarFrame, CloudError> {
        cloud.check()?;
        let rings = match (self.grid.row_from, &cloud.ring) {
            (RowSource::Ring, None) => return Err(CloudError::NoRing),
            (RowSource::Elevation, _) | (_, None) => None,
            (_, Some(r)) => Some(r.as_slice()),
        };
        if let Some(rings) = rings {
            if let Some(&ring) = rings.iter().find(|&&r| usize::from(r) >= self.grid.rows) {
                return Err(CloudError::RingOutOfRange {
                    ring,
                    rows: self.grid.rows,
                });
            }
            if self.top_first.is_none() {
                self.top_first = Some(ring_zero_is_top(cloud, rings));
            }
        }
        if !self.grid_needed {
            return Ok(self.points_only(cloud, index));
        }
        let (rows, cols) = (self.grid.rows, self.grid.cols);
        // Pass 1, in parallel: each point's corrected coordinates, column and pixel (the
        // trigonometry). Pass 2, in file order: the scan and the grid.
        let located: Vec<Located> = cloud
            .points
            .par_iter()
            .enumerate()
            .with_min_len(8192)
            .map(|(i, p)| self.locate(cloud, rings, i, p))
            .collect();
        let mut f = LidarFrame::empty(index, cloud.timestamp, rows, cols, Arc::clone(&self.beams));
        let period = self.period();
        let kept = located.iter().filter(|l| l.pixel != DROPPED).count();
        let mut scan = self.empty_scan(PointFields::of(cloud), kept, rows * cols);
        let mut time_samples = Vec::new();
        for (i, l) in located.iter().enumerate() {
            if l.pixel == DROPPED {
                continue;
            }
            let record = PointRecord::of(cloud, i);
            let k = self.push_point(&mut scan, &record, l.xyz, l.pixel, || l.col as usize);
            let file_time = cloud.time.as_ref().map(|t| t[i]);
            if l.pixel == ScanPoints::NONE {
                continue;
            }
            let pixel = l.pixel as usize;
            if let Some(t) = file_time {
                time_samples.push((l.col as usize, t));
            }
            if f.valid[pixel] && f.range[pixel] <= l.range {
                continue;
            }
            f.valid[pixel] = true;
            f.range[pixel] = l.range;
            f.points[pixel] = Point3::new(l.xyz[0] as f32, l.xyz[1] as f32, l.xyz[2] as f32);
            f.signal[pixel] = channel_value(cloud.intensity.as_deref(), i);
            f.reflectivity[pixel] = channel_value(cloud.reflectivity.as_deref(), i);
            f.near_ir[pixel] = channel_value(cloud.near_ir.as_deref(), i);
            scan.pixel_to_point[pixel] = k;
        }
        f.column_times = if cloud.time.is_some() {
            column_times(cloud.timestamp, cols, time_samples.into_iter())
        } else if let Some(period) = period {
            (0..cols)
                .map(|c| cloud.timestamp + period * c as f64 / cols as f64)
                .collect()
        } else {
            vec![cloud.timestamp; cols]
        };
        if let (Some(_), Some(times)) = (&cloud.time, &scan.times) {
            f.pixel_times = Some(pixel_times(&f, &scan.pixel_to_point, times));
        }
        f.scan = Some(Arc::new(scan));
        Ok(f)
    }

    /// The frame of `cloud` without an image grid: its finite points with their times,
    /// intensities and rings, none of them in a pixel.
    fn points_only(&self, cloud: &RawCloud, index: u64) -> LidarFrame {
        let records = (0..cloud.len()).map(|i| PointRecord::of(cloud, i));
        let fields = PointFields::of(cloud);
        self.records_only(cloud.timestamp, (fields, cloud.len()), records, index)
    }

    /// The frame [`Projector::project`] makes when no grid is needed
    /// ([`Projector::grid_needed`] is false), straight from a source's points (e.g. a
    /// message's bytes) instead of a [`RawCloud`]: the `records` of a cloud stamped
    /// `timestamp`, `n` of them at most, each carrying the `fields` named. For points without
    /// a ring: rings are checked against the whole cloud first, so a cloud with rings goes
    /// through [`Projector::project`] (rings given here are left out of the frame).
    /// `Err(CloudError::NoRing)` when the grid's rows come from rings.
    pub fn points_only_from(
        &self,
        timestamp: f64,
        (fields, n): (PointFields, usize),
        records: impl Iterator<Item = PointRecord>,
        index: u64,
    ) -> Result<LidarFrame, CloudError> {
        if self.grid.row_from == RowSource::Ring {
            return Err(CloudError::NoRing);
        }
        let fields = PointFields {
            ring: false,
            ..fields
        };
        Ok(self.records_only(timestamp, (fields, n), records, index))
    }

    /// [`Projector::points_only_from`] for records whose rings, if any, were checked.
    fn records_only(
        &self,
        timestamp: f64,
        (fields, n): (PointFields, usize),
        records: impl Iterator<Item = PointRecord>,
        index: u64,
    ) -> LidarFrame {
        let cols = self.grid.cols;
        let mut scan = self.empty_scan(fields, n, 0);
        for r in records {
            if let Some(v) = self.corrected(&r) {
                let col = || azimuth_column(v[0], v[1], cols);
                self.push_point(&mut scan, &r, v, ScanPoints::NONE, col);
            }
        }
        let mut f = LidarFrame::empty(index, timestamp, 0, 0, Arc::clone(&self.beams));
        f.scan = Some(Arc::new(scan));
        f
    }

    /// Revolution time when the grid knows the rate (points without a time of their own are
    /// then timed by azimuth).
    fn period(&self) -> Option<f64> {
        (self.grid.frame_rate_hz > 0.0).then(|| 1.0 / self.grid.frame_rate_hz)
    }

    /// A scan with room for `n` points, the per-point `fields` of the cloud (times also when
    /// they are spread by azimuth) and a grid of `pixels` empty pixels.
    fn empty_scan(&self, fields: PointFields, n: usize, pixels: usize) -> ScanPoints {
        let timed = fields.time || self.period().is_some();
        ScanPoints {
            points: Vec::with_capacity(n),
            times: timed.then(|| Vec::with_capacity(n)),
            intensity: fields.intensity.then(|| Vec::with_capacity(n)),
            ring: fields.ring.then(|| Vec::with_capacity(n)),
            source_index: Vec::with_capacity(n),
            pixel: Vec::with_capacity(n),
            pixel_to_point: vec![ScanPoints::NONE; pixels],
        }
    }

    /// Appends point `r` (coordinates `xyz`, in `pixel`) to `scan`; without a time its time
    /// is that of its azimuth column (`col`, asked only then). Returns its index in the scan.
    fn push_point(
        &self,
        scan: &mut ScanPoints,
        r: &PointRecord,
        xyz: [f64; 3],
        pixel: u32,
        col: impl FnOnce() -> usize,
    ) -> u32 {
        let k = scan.points.len() as u32;
        scan.points.push(Point3::from(xyz));
        scan.source_index.push(r.index);
        scan.pixel.push(pixel);
        if let (Some(out), Some(v)) = (scan.intensity.as_mut(), r.intensity) {
            out.push(v);
        }
        if let (Some(out), Some(ring)) = (scan.ring.as_mut(), r.ring) {
            out.push(ring);
        }
        if let Some(out) = scan.times.as_mut() {
            let spread = || self.period().unwrap_or(0.0) * col() as f64 / self.grid.cols as f64;
            out.push(r.time.unwrap_or_else(spread));
        }
        k
    }

    /// Point `r` in double precision and corrected; `None` for a point with a non-finite
    /// coordinate or time (before or after the correction).
    fn corrected(&self, r: &PointRecord) -> Option<[f64; 3]> {
        let time_ok = r.time.is_none_or(f64::is_finite);
        let p = r.xyz;
        let v = [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])];
        if !time_ok || !v.iter().all(|x| x.is_finite()) {
            return None;
        }
        let v = self.correction.as_ref().map_or(v, |c| c.apply(v));
        v.iter().all(|x| x.is_finite()).then_some(v)
    }

    /// Where point `i` (`p`) of `cloud` goes: [`DROPPED`] for a point with a non-finite
    /// coordinate or time (before or after the correction), [`ScanPoints::NONE`] for one
    /// outside the grid.
    fn locate(&self, cloud: &RawCloud, rings: Option<&[u16]>, i: usize, p: &[f32; 3]) -> Located {
        let time = cloud.time.as_ref().map(|t| t[i]);
        let record = PointRecord {
            index: i as u32,
            xyz: *p,
            time,
            intensity: None,
            ring: None,
        };
        let Some(v) = self.corrected(&record) else {
            return Located {
                xyz: [0.0; 3],
                pixel: DROPPED,
                col: 0,
                range: 0.0,
            };
        };
        let cols = self.grid.cols;
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let col = azimuth_column(v[0], v[1], cols);
        let row = if norm == 0.0 {
            None
        } else {
            match rings {
                Some(r) => Some(self.ring_row(r[i])),
                None => self.lookup.row_of_sin(v[2] / norm),
            }
        };
        Located {
            xyz: v,
            pixel: row.map_or(ScanPoints::NONE, |r| (r * cols + col) as u32),
            col: col as u32,
            range: cloud.range.as_ref().map_or(norm as f32, |r| r[i]),
        }
    }

    fn ring_row(&self, ring: u16) -> usize {
        let r = usize::from(ring);
        if self.top_first.unwrap_or(true) {
            r
        } else {
            self.grid.rows - 1 - r
        }
    }
}

/// The time of the point kept in each pixel (`times` are the scan points' times); empty
/// pixels get their column's time.
fn pixel_times(f: &LidarFrame, pixel_to_point: &[u32], times: &[f64]) -> Vec<f64> {
    pixel_to_point
        .iter()
        .enumerate()
        .map(|(p, &i)| match times.get(i as usize) {
            Some(t) if i != ScanPoints::NONE => f.timestamp + t,
            _ => f.column_times[p % f.cols],
        })
        .collect()
}

fn channel_value(values: Option<&[f32]>, i: usize) -> f32 {
    values
        .and_then(|v| v.get(i))
        .copied()
        .filter(|v| v.is_finite())
        .unwrap_or(0.0)
}

/// Where a point goes ([`Projector::locate`]).
struct Located {
    /// Coordinates, corrected.
    xyz: [f64; 3],
    /// Row-major pixel, [`ScanPoints::NONE`] outside the grid, [`DROPPED`] not kept.
    pixel: u32,
    /// Azimuth column (also for points outside the grid).
    col: u32,
    range: f32,
}

/// [`Located::pixel`] of a point that is not kept (non-finite).
const DROPPED: u32 = u32::MAX - 1;

/// True when ring 0's points lie above those of the highest ring.
fn ring_zero_is_top(cloud: &RawCloud, rings: &[u16]) -> bool {
    let max_ring = rings.iter().copied().max().unwrap_or(0);
    let mut sums = [(0.0f64, 0usize); 2];
    for (p, &r) in cloud.points.iter().zip(rings) {
        let slot = if r == 0 {
            0
        } else if r == max_ring {
            1
        } else {
            continue;
        };
        let norm = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        if norm.is_finite() && norm > 0.0 {
            sums[slot].0 += f64::from(p[2] / norm);
            sums[slot].1 += 1;
        }
    }
    let mean = |(s, n): (f64, usize)| if n == 0 { 0.0 } else { s / n as f64 };
    mean(sums[0]) >= mean(sums[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(az_deg: f64, el_deg: f64, r: f64) -> [f32; 3] {
        let (az, el) = (az_deg.to_radians(), el_deg.to_radians());
        [
            (r * el.cos() * az.cos()) as f32,
            (r * el.cos() * az.sin()) as f32,
            (r * el.sin()) as f32,
        ]
    }

    fn config(rows: usize, cols: usize) -> ProjectionConfig {
        ProjectionConfig {
            rows: Some(rows),
            cols: Some(cols),
            fov_up_deg: Some(10.0),
            fov_down_deg: Some(-10.0),
            ..ProjectionConfig::default()
        }
    }

    fn projector(c: ProjectionConfig) -> Result<Projector, CloudError> {
        Projector::from_config(&c, Sensor::Generic)
    }

    #[test]
    fn elevation_bins_to_the_nearest_row_and_drops_outside() {
        let mut p = projector(config(3, 8)).unwrap();
        let cloud = RawCloud {
            points: vec![
                point(0.0, 9.0, 5.0),
                point(0.0, -1.0, 5.0),
                point(0.0, -30.0, 5.0),
            ],
            ..RawCloud::default()
        };
        let f = p.project(&cloud, 0).unwrap();
        let scan = f.scan.as_ref().unwrap();
        assert_eq!(scan.pixel, vec![0, 8, ScanPoints::NONE]);
        assert_eq!(scan.pixel_to_point[0], 0);
        // The point below the field of view has no pixel but stays in the frame.
        assert_eq!(f.to_cloud().len(), 3);
        assert_eq!(f.valid_count(), 2);
        assert!((f.range[8] - 5.0).abs() < 1e-5);
    }

    #[test]
    fn the_nearest_point_wins_a_pixel() {
        let one_beam = ProjectionConfig {
            altitudes_deg: Some(vec![0.0]),
            ..config(1, 4)
        };
        let mut p = projector(one_beam).unwrap();
        let cloud = RawCloud {
            points: vec![
                point(0.0, 0.0, 9.0),
                point(1.0, 0.0, 4.0),
                point(-1.0, 0.0, 6.0),
            ],
            intensity: Some(vec![1.0, 2.0, 3.0]),
            ..RawCloud::default()
        };
        let f = p.project(&cloud, 0).unwrap();
        let scan = f.scan.as_ref().unwrap();
        assert!(f.pixel_times.is_none());
        assert_eq!(scan.pixel_to_point[0], 1);
        assert_eq!(scan.pixel, vec![0, 0, 0]);
        assert_eq!(f.signal[0], 2.0);
        // Every point reaches the cloud, in file order, with its own intensity.
        let all = f.to_cloud();
        assert_eq!(all.intensities, Some(vec![1.0, 2.0, 3.0]));
        assert_eq!(f.cloud(keylo_core::PixelPoints::Nearest).len(), 1);
    }

    #[test]
    fn ring_order_is_detected_from_elevations() {
        let mut p = projector(config(2, 4)).unwrap();
        let cloud = RawCloud {
            points: vec![point(0.0, -5.0, 5.0), point(0.0, 5.0, 5.0)],
            ring: Some(vec![0, 1]), // ring 0 is the lower beam: Velodyne order
            ..RawCloud::default()
        };
        let f = p.project(&cloud, 0).unwrap();
        let scan = f.scan.as_ref().unwrap();
        assert_eq!(scan.pixel, vec![4, 0]);
        let bad = RawCloud {
            points: vec![point(0.0, 0.0, 1.0)],
            ring: Some(vec![7]),
            ..RawCloud::default()
        };
        assert_eq!(
            p.project(&bad, 1).unwrap_err(),
            CloudError::RingOutOfRange { ring: 7, rows: 2 }
        );
    }

    #[test]
    fn beam_tables_and_times() {
        let c = ProjectionConfig {
            altitudes_deg: Some(vec![-2.0, 2.0]),
            cols: Some(4),
            frame_rate_hz: 10.0,
            ..ProjectionConfig::default()
        };
        let mut p = projector(c).unwrap();
        assert_eq!(p.beams().altitude_deg, vec![2.0, -2.0]);
        let cloud = RawCloud {
            timestamp: 1.0,
            points: vec![point(0.0, -1.9, 3.0)],
            ..RawCloud::default()
        };
        let f = p.project(&cloud, 0).unwrap();
        assert!(f.valid[4]);
        assert!((f.column_times[2] - 1.05).abs() < 1e-12);
        let bad = ProjectionConfig {
            fov_up_deg: Some(-30.0),
            ..ProjectionConfig::default()
        };
        assert!(projector(bad)
            .unwrap_err()
            .to_string()
            .contains("fov_up_deg"));
    }
}
