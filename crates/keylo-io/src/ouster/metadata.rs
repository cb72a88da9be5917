//! The Ouster sensor metadata JSON, parsed as ouster-sdk 1.0 parses it, including its defaults
//! for old files that lack fields (checked against ouster-sdk on the sample files:
//! `tests/ouster_metadata.rs`).

use std::path::Path;

use nalgebra::Matrix4;

use super::json::Node;
use crate::IoError;

/// The UDP lidar packet profile.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UdpProfile {
    /// The original packet format (firmware ≤ 2.x default).
    Legacy,
    /// Single return: 19-bit range, 8-bit reflectivity, 16-bit signal and near-IR.
    Rng19Rfl8Sig16Nir16,
    /// Dual return variant of the above.
    Rng19Rfl8Sig16Nir16Dual,
    /// Low data rate: 15-bit range, 8-bit reflectivity and near-IR.
    Rng15Rfl8Nir8,
    /// Any other profile, kept by name (reading its packets is an error naming it).
    Other(String),
}

impl UdpProfile {
    fn parse(name: &str) -> Self {
        match name {
            "LEGACY" => Self::Legacy,
            "RNG19_RFL8_SIG16_NIR16" => Self::Rng19Rfl8Sig16Nir16,
            "RNG19_RFL8_SIG16_NIR16_DUAL" => Self::Rng19Rfl8Sig16Nir16Dual,
            "RNG15_RFL8_NIR8" => Self::Rng15Rfl8Nir8,
            other => Self::Other(other.to_string()),
        }
    }

    /// The profile's name as Ouster writes it.
    pub fn name(&self) -> &str {
        match self {
            Self::Legacy => "LEGACY",
            Self::Rng19Rfl8Sig16Nir16 => "RNG19_RFL8_SIG16_NIR16",
            Self::Rng19Rfl8Sig16Nir16Dual => "RNG19_RFL8_SIG16_NIR16_DUAL",
            Self::Rng15Rfl8Nir8 => "RNG15_RFL8_NIR8",
            Self::Other(name) => name,
        }
    }

    /// Returns per pixel.
    pub fn returns(&self) -> usize {
        if matches!(self, Self::Rng19Rfl8Sig16Nir16Dual) {
            2
        } else {
            1
        }
    }
}

/// What keylo needs of an Ouster sensor's metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct OusterMetadata {
    /// Product line, e.g. `OS-0-128` (empty when the file does not say).
    pub prod_line: String,
    /// Firmware build revision, e.g. `v3.0.1` (empty when the file does not say).
    pub fw_rev: String,
    /// Serial number, when the file has one (lidar packets of other profiles than LEGACY
    /// carry it too).
    pub prod_sn: Option<u64>,
    /// Initialisation id of the sensor session, when the file has one (also in packets).
    pub init_id: Option<u32>,
    /// UDP destination port of lidar packets, when the file says.
    pub udp_port_lidar: Option<u16>,
    /// Lidar mode, e.g. `1024x10`.
    pub lidar_mode: String,
    pub columns_per_frame: usize,
    pub pixels_per_column: usize,
    pub columns_per_packet: usize,
    /// First and last column the sensor sends (inclusive). An azimuth window across the
    /// frame's start wraps: `first > last` means columns `first..cols` and `0..=last`.
    pub column_window: (usize, usize),
    /// Staggering: row `r` is shifted by this many columns in the raw (staggered) image.
    pub pixel_shift_by_row: Vec<i64>,
    pub udp_profile_lidar: UdpProfile,
    pub fps: u32,
    /// Beam elevations, degrees, row 0 first.
    pub beam_altitude_angles: Vec<f64>,
    /// Beam azimuth offsets, degrees.
    pub beam_azimuth_angles: Vec<f64>,
    pub lidar_origin_to_beam_origin_mm: f64,
    /// Beam frame → lidar frame (translation in millimetres).
    pub beam_to_lidar_transform: Matrix4<f64>,
    /// Lidar frame → sensor frame (translation in millimetres).
    pub lidar_to_sensor_transform: Matrix4<f64>,
}

/// ouster-sdk's values for files that predate these fields (an OS1 gen-1 sensor).
const DEFAULT_ORIGIN_TO_BEAM_MM: f64 = 12.163;
const DEFAULT_LIDAR_TO_SENSOR: [f64; 16] = [
    -1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 36.18, 0.0, 0.0, 0.0, 1.0,
];
const DEFAULT_COLUMNS_PER_PACKET: usize = 16;

/// Whether column `c` lies in the column window `(first, last)` (inclusive; wrapped when
/// `first > last`, as ouster-sdk reads an azimuth window across the frame's start).
pub(crate) fn in_column_window((first, last): (usize, usize), c: usize) -> bool {
    if first <= last {
        (first..=last).contains(&c)
    } else {
        c >= first || c <= last
    }
}

impl OusterMetadata {
    /// Reads and parses a metadata file.
    pub fn read(path: &Path) -> Result<Self, IoError> {
        let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
        Self::parse(path, &text)
    }

    /// Parses metadata text; `path` names it in errors.
    pub fn parse(path: &Path, text: &str) -> Result<Self, IoError> {
        let value: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| IoError::format(path, format!("not valid JSON: {e}")))?;
        let root = Node::root(path, &value);
        if !value.is_object() {
            return Err(IoError::format(
                path,
                "expected a JSON object of Ouster sensor metadata",
            ));
        }
        let meta = match root.child("beam_intrinsics") {
            Some(beams) => Self::parse_nested(&root, &beams)?,
            None => Self::parse_legacy(&root)?,
        };
        meta.check(path)?;
        Ok(meta)
    }

    /// Firmware 3.x layout.
    fn parse_nested(root: &Node, beams: &Node) -> Result<Self, IoError> {
        let format = root
            .child("lidar_data_format")
            .ok_or_else(|| missing(root, "lidar_data_format"))?;
        let lidar_mode = root
            .child("config_params")
            .map(|c| c.opt_str("lidar_mode"))
            .transpose()?
            .flatten()
            .unwrap_or_default()
            .to_string();
        let altitude = beams.f64s("beam_altitude_angles")?;
        let info = root.child("sensor_info");
        let text = |key: &str| -> Result<String, IoError> {
            Ok(info
                .as_ref()
                .map(|i| i.opt_str(key))
                .transpose()?
                .flatten()
                .unwrap_or_default()
                .to_string())
        };
        let lidar_to_sensor = root
            .child("lidar_intrinsics")
            .map(|l| l.opt_f64s_len("lidar_to_sensor_transform", 16))
            .transpose()?
            .flatten();
        let mut meta = Self::from_format(&format, &lidar_mode, altitude.len())?;
        meta.prod_line = text("prod_line")?;
        meta.fw_rev = text("build_rev")?;
        if let Some(info) = &info {
            meta.read_identity(info)?;
        }
        if let Some(config) = root.child("config_params") {
            meta.udp_port_lidar = port(&config)?;
        }
        meta.with_beams(beams, altitude, lidar_to_sensor)
    }

    /// Firmware ≤ 2.x layout: flat keys, `data_format` optional.
    fn parse_legacy(root: &Node) -> Result<Self, IoError> {
        let altitude = root.f64s("beam_altitude_angles")?;
        let lidar_mode = root.opt_str("lidar_mode")?.unwrap_or_default().to_string();
        let mut meta = match root.child("data_format") {
            Some(format) => Self::from_format(&format, &lidar_mode, altitude.len())?,
            None => Self::default_format(root, &lidar_mode, altitude.len())?,
        };
        let lidar_to_sensor = root.opt_f64s_len("lidar_to_sensor_transform", 16)?;
        meta.prod_line = root.opt_str("prod_line")?.unwrap_or_default().to_string();
        meta.fw_rev = root.opt_str("build_rev")?.unwrap_or_default().to_string();
        meta.read_identity(root)?;
        meta.udp_port_lidar = port(root)?;
        meta.with_beams(root, altitude, lidar_to_sensor)
    }

    /// Serial number and initialisation id from `node`.
    fn read_identity(&mut self, node: &Node) -> Result<(), IoError> {
        self.prod_sn = node.opt_u64_lenient("prod_sn")?;
        self.init_id = node
            .opt_u64_lenient("initialization_id")?
            .and_then(|v| u32::try_from(v).ok());
        Ok(())
    }

    /// The beam intrinsics from `beams` (the nested `beam_intrinsics` object, or the root of
    /// the legacy layout) and the lidar → sensor transform, with ouster-sdk's defaults.
    fn with_beams(
        mut self,
        beams: &Node,
        altitude: Vec<f64>,
        lidar_to_sensor: Option<Vec<f64>>,
    ) -> Result<Self, IoError> {
        let origin = beams
            .opt_f64("lidar_origin_to_beam_origin_mm")?
            .unwrap_or(DEFAULT_ORIGIN_TO_BEAM_MM);
        self.beam_azimuth_angles = beams.f64s("beam_azimuth_angles")?;
        self.beam_altitude_angles = altitude;
        self.lidar_origin_to_beam_origin_mm = origin;
        self.beam_to_lidar_transform = beam_to_lidar(beams, origin)?;
        self.lidar_to_sensor_transform = matrix(
            lidar_to_sensor
                .as_deref()
                .unwrap_or(&DEFAULT_LIDAR_TO_SENSOR),
        );
        Ok(self)
    }

    /// The data-format fields of a `data_format` / `lidar_data_format` object.
    fn from_format(format: &Node, lidar_mode: &str, beams: usize) -> Result<Self, IoError> {
        let (mode_cols, mode_fps) = parse_mode(lidar_mode);
        let cols = format
            .opt_usize("columns_per_frame")?
            .or(mode_cols)
            .ok_or_else(|| missing(format, "columns_per_frame"))?;
        let window = match format.opt_i64s("column_window")? {
            Some(w) if w.len() == 2 && w.iter().all(|v| *v >= 0) => (w[0] as usize, w[1] as usize),
            Some(_) => {
                return Err(IoError::format(
                    format.file,
                    format!(
                        "metadata key `{}.column_window`: expected [first, last]",
                        format.path
                    ),
                ))
            }
            None => (0, cols.saturating_sub(1)),
        };
        let rows = format.opt_usize("pixels_per_column")?.unwrap_or(beams);
        Ok(Self {
            lidar_mode: if lidar_mode.is_empty() {
                format!("{cols}x{}", mode_fps.unwrap_or(10))
            } else {
                lidar_mode.to_string()
            },
            columns_per_frame: cols,
            pixels_per_column: rows,
            columns_per_packet: format
                .opt_usize("columns_per_packet")?
                .unwrap_or(DEFAULT_COLUMNS_PER_PACKET),
            column_window: window,
            pixel_shift_by_row: format
                .opt_i64s("pixel_shift_by_row")?
                .unwrap_or_else(|| default_shift(cols, rows)),
            udp_profile_lidar: UdpProfile::parse(
                format.opt_str("udp_profile_lidar")?.unwrap_or("LEGACY"),
            ),
            fps: format
                .opt_usize("fps")?
                .map(|f| f as u32)
                .or(mode_fps)
                .unwrap_or(10),
            ..Self::empty()
        })
    }

    /// ouster-sdk's data format for files without one: every `from_format` default (LEGACY
    /// profile, nominal staggering), with the columns taken from `lidar_mode`.
    fn default_format(root: &Node, lidar_mode: &str, beams: usize) -> Result<Self, IoError> {
        if parse_mode(lidar_mode).0.is_none() {
            return Err(missing(root, "lidar_mode (or data_format)"));
        }
        static ABSENT: serde_json::Value = serde_json::Value::Null;
        let format = Node {
            file: root.file,
            path: "data_format".into(),
            value: &ABSENT,
        };
        Self::from_format(&format, lidar_mode, beams)
    }

    fn empty() -> Self {
        Self {
            prod_line: String::new(),
            fw_rev: String::new(),
            prod_sn: None,
            init_id: None,
            udp_port_lidar: None,
            lidar_mode: String::new(),
            columns_per_frame: 0,
            pixels_per_column: 0,
            columns_per_packet: DEFAULT_COLUMNS_PER_PACKET,
            column_window: (0, 0),
            pixel_shift_by_row: Vec::new(),
            udp_profile_lidar: UdpProfile::Legacy,
            fps: 10,
            beam_altitude_angles: Vec::new(),
            beam_azimuth_angles: Vec::new(),
            lidar_origin_to_beam_origin_mm: DEFAULT_ORIGIN_TO_BEAM_MM,
            beam_to_lidar_transform: Matrix4::identity(),
            lidar_to_sensor_transform: matrix(&DEFAULT_LIDAR_TO_SENSOR),
        }
    }

    /// Consistency of the sizes; errors name the file and the field.
    fn check(&self, path: &Path) -> Result<(), IoError> {
        let rows = self.pixels_per_column;
        let lists = [
            ("beam_altitude_angles", self.beam_altitude_angles.len()),
            ("beam_azimuth_angles", self.beam_azimuth_angles.len()),
            ("pixel_shift_by_row", self.pixel_shift_by_row.len()),
        ];
        for (name, len) in lists {
            if len != rows {
                return Err(IoError::format(
                    path,
                    format!("`{name}` has {len} entries, expected pixels_per_column = {rows}"),
                ));
            }
        }
        if self.columns_per_frame > MAX_COLUMNS || rows > MAX_ROWS {
            return Err(IoError::format(
                path,
                format!(
                    "{} columns x {rows} rows per frame: Ouster sensors have at most {MAX_COLUMNS} \
                     columns (lidar mode 4096x5) and {MAX_ROWS} rows",
                    self.columns_per_frame
                ),
            ));
        }
        let (first, last) = self.column_window;
        if rows == 0
            || self.columns_per_frame == 0
            || self.columns_per_packet == 0
            || first >= self.columns_per_frame
            || last >= self.columns_per_frame
        {
            return Err(IoError::format(
                path,
                format!(
                    "inconsistent data format: {} columns x {rows} rows, {} columns per packet, column window [{first}, {last}]",
                    self.columns_per_frame, self.columns_per_packet
                ),
            ));
        }
        Ok(())
    }
}

/// The most columns per frame of any Ouster lidar mode (`4096x5`).
const MAX_COLUMNS: usize = 4096;
/// Rows per frame accepted (Ouster sensors have at most 128 beams).
const MAX_ROWS: usize = 256;

fn missing(node: &Node, key: &str) -> IoError {
    let path = if node.path.is_empty() {
        key.to_string()
    } else {
        format!("{}.{key}", node.path)
    };
    IoError::format(node.file, format!("metadata key `{path}` is missing"))
}

/// `"1024x10"` → (1024 columns, 10 Hz).
/// `udp_port_lidar` of `node`, when present and not 0.
fn port(node: &Node) -> Result<Option<u16>, IoError> {
    Ok(node
        .opt_u64_lenient("udp_port_lidar")?
        .and_then(|p| u16::try_from(p).ok())
        .filter(|&p| p != 0))
}

fn parse_mode(mode: &str) -> (Option<usize>, Option<u32>) {
    let mut parts = mode.split('x');
    let cols = parts.next().and_then(|c| c.parse().ok());
    let fps = parts.next().and_then(|f| f.parse().ok());
    (cols, fps)
}

/// ouster-sdk's nominal staggering for files without `pixel_shift_by_row`.
fn default_shift(cols: usize, rows: usize) -> Vec<i64> {
    let pattern: [i64; 4] = match cols {
        512 => [9, 6, 3, 0],
        1024 => [18, 12, 6, 0],
        2048 => [36, 24, 12, 0],
        _ => [0; 4],
    };
    (0..rows).map(|r| pattern[r % 4]).collect()
}

/// `beam_to_lidar_transform` if the node has one, else the translation `origin` mm along x.
fn beam_to_lidar(node: &Node, origin: f64) -> Result<Matrix4<f64>, IoError> {
    Ok(match node.opt_f64s_len("beam_to_lidar_transform", 16)? {
        Some(v) => matrix(&v),
        None => {
            let mut m = Matrix4::identity();
            m[(0, 3)] = origin;
            m
        }
    })
}

/// A row-major 4x4 matrix from 16 numbers.
fn matrix(v: &[f64]) -> Matrix4<f64> {
    Matrix4::from_row_slice(v)
}
