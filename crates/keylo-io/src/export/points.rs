//! The per-point values of a frame that point-cloud exports carry.

use std::fmt;
use std::str::FromStr;

use keylo_core::LidarFrame;

/// A per-point value besides x y z.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportField {
    /// Signal (intensity), float32.
    Signal,
    /// Reflectivity, float32.
    Reflectivity,
    /// Near-IR, float32.
    NearIr,
    /// Range, metres, float32.
    Range,
    /// The pixel's row (beam), uint16.
    Ring,
    /// Firing time relative to the frame time, seconds, float32.
    Time,
}

impl ExportField {
    /// Every field, in the order they are written.
    pub const ALL: [ExportField; 6] = [
        Self::Signal,
        Self::Reflectivity,
        Self::NearIr,
        Self::Range,
        Self::Ring,
        Self::Time,
    ];

    /// The field's name in PLY/PCD headers (the names keylo's readers and PCL use).
    pub fn name(self) -> &'static str {
        match self {
            Self::Signal => "intensity",
            Self::Reflectivity => "reflectivity",
            Self::NearIr => "ambient",
            Self::Range => "range",
            Self::Ring => "ring",
            Self::Time => "t",
        }
    }

    /// The name on the command line (`--channels`).
    pub fn cli_name(self) -> &'static str {
        match self {
            Self::Signal => "signal",
            Self::Reflectivity => "reflectivity",
            Self::NearIr => "near-ir",
            Self::Range => "range",
            Self::Ring => "ring",
            Self::Time => "time",
        }
    }

    /// Whether the value is written as uint16 (else float32).
    pub fn is_u16(self) -> bool {
        self == Self::Ring
    }
}

impl fmt::Display for ExportField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.cli_name())
    }
}

impl FromStr for ExportField {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|f| f.cli_name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|f| f.cli_name()).collect();
                format!("unknown channel `{s}`; allowed: {}", names.join(", "))
            })
    }
}

/// The points of a frame with the chosen fields, ready to write: every valid, finite pixel
/// of an organised frame; every point of an unorganised scan (`LidarFrame::scan`), not only
/// the one per pixel its images show.
pub struct ExportPoints<'a> {
    frame: &'a LidarFrame,
    /// Indices of the points: row-major pixels, or scan points when the frame has a scan.
    pub items: Vec<usize>,
    pub fields: Vec<ExportField>,
}

impl<'a> ExportPoints<'a> {
    /// The points of `frame` with `fields`.
    pub fn new(frame: &'a LidarFrame, fields: &[ExportField]) -> Self {
        let items = match &frame.scan {
            Some(scan) => (0..scan.len()).collect(),
            None => (0..frame.rows * frame.cols)
                .filter(|&i| frame.valid[i] && frame.points[i].coords.iter().all(|v| v.is_finite()))
                .collect(),
        };
        Self {
            frame,
            items,
            fields: fields.to_vec(),
        }
    }

    /// x y z of item `i`.
    pub fn xyz(&self, i: usize) -> [f32; 3] {
        match &self.frame.scan {
            Some(scan) => {
                let p = scan.points[i];
                [p.x as f32, p.y as f32, p.z as f32]
            }
            None => {
                let p = self.frame.points[i];
                [p.x, p.y, p.z]
            }
        }
    }

    /// Field `f` of item `i` as float (ring as its integer value). A scan point has its own
    /// intensity, range, time and ring (its pixel's row without a ring field); reflectivity
    /// and near-IR are its pixel's when it is the point the pixel shows, else 0.
    pub fn value(&self, f: ExportField, i: usize) -> f32 {
        let fr = self.frame;
        let Some(scan) = &fr.scan else {
            return match f {
                ExportField::Signal => fr.signal[i],
                ExportField::Reflectivity => fr.reflectivity[i],
                ExportField::NearIr => fr.near_ir[i],
                ExportField::Range => fr.range[i],
                ExportField::Ring => (i / fr.cols) as f32,
                ExportField::Time => (fr.pixel_time(i) - fr.timestamp) as f32,
            };
        };
        let pixel = scan.pixel[i] as usize;
        let shown = scan
            .pixel_to_point
            .get(pixel)
            .is_some_and(|&k| k as usize == i);
        match f {
            ExportField::Signal => scan.intensity.as_ref().map_or(0.0, |v| v[i]),
            ExportField::Reflectivity if shown => fr.reflectivity[pixel],
            ExportField::NearIr if shown => fr.near_ir[pixel],
            ExportField::Reflectivity | ExportField::NearIr => 0.0,
            ExportField::Range => scan.points[i].coords.norm() as f32,
            ExportField::Ring => match &scan.ring {
                Some(r) => f32::from(r[i]),
                None if pixel < fr.rows * fr.cols => (pixel / fr.cols) as f32,
                None => 0.0,
            },
            ExportField::Time => scan.times.as_ref().map_or(0.0, |t| t[i]) as f32,
        }
    }

    /// The little-endian bytes of every point: x y z then the fields.
    pub fn binary_le(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.items.len() * (12 + 4 * self.fields.len()));
        for &i in &self.items {
            for v in self.xyz(i) {
                out.extend_from_slice(&v.to_le_bytes());
            }
            for &f in &self.fields {
                let v = self.value(f, i);
                if f.is_u16() {
                    out.extend_from_slice(&(v as u16).to_le_bytes());
                } else {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        out
    }
}
