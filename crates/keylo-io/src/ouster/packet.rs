//! Lidar packet layouts (profiles LEGACY, RNG19_RFL8_SIG16_NIR16, RNG15_RFL8_NIR8) and
//! decoding of their columns into a staggered frame. Byte layouts follow Ouster's sensor
//! documentation; all fields are little-endian.

use super::metadata::{OusterMetadata, UdpProfile};

/// The staggered channels of one frame as the packets carry them: column-major (pixel
/// `(row, column)` at `column * rows + row`), the order packets hold them in.
#[derive(Debug, Clone, PartialEq)]
pub struct RawFrame {
    pub frame_id: u32,
    pub rows: usize,
    pub cols: usize,
    /// Range, millimetres (0 = no return).
    pub range_mm: Vec<u32>,
    pub signal: Vec<u32>,
    pub reflectivity: Vec<u32>,
    pub near_ir: Vec<u32>,
    /// Second return of dual-return profiles (empty otherwise): range (mm), signal,
    /// reflectivity.
    pub range2_mm: Vec<u32>,
    pub signal2: Vec<u32>,
    pub reflectivity2: Vec<u32>,
    /// Column time stamps, nanoseconds (0 when the column was not received).
    pub column_ns: Vec<u64>,
    /// Whether a valid column arrived.
    pub column_valid: Vec<bool>,
    /// Valid columns whose measurement id was not below the column count (a metadata JSON
    /// of another lidar mode); they are dropped.
    pub out_of_range_columns: usize,
}

impl RawFrame {
    fn new(frame_id: u32, rows: usize, cols: usize, returns: usize) -> Self {
        let n = rows * cols;
        let n2 = if returns > 1 { n } else { 0 };
        Self {
            range2_mm: vec![0; n2],
            signal2: vec![0; n2],
            reflectivity2: vec![0; n2],
            frame_id,
            rows,
            cols,
            range_mm: vec![0; n],
            signal: vec![0; n],
            reflectivity: vec![0; n],
            near_ir: vec![0; n],
            column_ns: vec![0; cols],
            column_valid: vec![false; cols],
            out_of_range_columns: 0,
        }
    }

    /// Makes a used frame a new one numbered `frame_id` without clearing its pixel buffers:
    /// every column received overwrites its pixels, and [`Self::clear_missing_columns`]
    /// zeroes the others when the frame is complete, so the result equals a fresh frame.
    pub fn reuse(&mut self, frame_id: u32) {
        self.frame_id = frame_id;
        self.column_ns.fill(0);
        self.column_valid.fill(false);
        self.out_of_range_columns = 0;
    }

    /// Zeroes the pixels of every column that did not arrive (stale after [`Self::reuse`]).
    pub fn clear_missing_columns(&mut self) {
        let rows = self.rows;
        for m in (0..self.cols).filter(|&m| !self.column_valid[m]) {
            let span = m * rows..(m + 1) * rows;
            for buf in [
                &mut self.range_mm,
                &mut self.signal,
                &mut self.reflectivity,
                &mut self.near_ir,
                &mut self.range2_mm,
                &mut self.signal2,
                &mut self.reflectivity2,
            ] {
                if let Some(px) = buf.get_mut(span.clone()) {
                    px.fill(0);
                }
            }
        }
    }
}

/// Where the fields of one packet profile are.
#[derive(Debug, Clone)]
pub struct PacketFormat {
    profile: UdpProfile,
    rows: usize,
    cols: usize,
    columns_per_packet: usize,
    header: usize,
    column_header: usize,
    pixel: usize,
    column_footer: usize,
    footer: usize,
}

/// An Ouster UDP lidar profile keylo does not decode yet.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "UDP lidar profile {profile} is not supported yet (supported: LEGACY, \
     RNG19_RFL8_SIG16_NIR16, RNG19_RFL8_SIG16_NIR16_DUAL, RNG15_RFL8_NIR8)"
)]
pub struct UnsupportedProfile {
    pub profile: String,
}

impl PacketFormat {
    /// The layout for `meta`'s profile; an error names an unsupported profile.
    pub fn new(meta: &OusterMetadata) -> Result<Self, UnsupportedProfile> {
        let (header, column_header, pixel, column_footer, footer) = match meta.udp_profile_lidar {
            UdpProfile::Legacy => (0, 16, 12, 4, 0),
            UdpProfile::Rng19Rfl8Sig16Nir16 => (32, 12, 12, 0, 32),
            UdpProfile::Rng19Rfl8Sig16Nir16Dual => (32, 12, 16, 0, 32),
            UdpProfile::Rng15Rfl8Nir8 => (32, 12, 4, 0, 32),
            ref other => {
                return Err(UnsupportedProfile {
                    profile: other.name().to_string(),
                })
            }
        };
        Ok(Self {
            profile: meta.udp_profile_lidar.clone(),
            rows: meta.pixels_per_column,
            cols: meta.columns_per_frame,
            columns_per_packet: meta.columns_per_packet,
            header,
            column_header,
            pixel,
            column_footer,
            footer,
        })
    }

    fn column_size(&self) -> usize {
        self.column_header + self.rows * self.pixel + self.column_footer
    }

    /// The profile's name.
    pub fn profile_name(&self) -> &str {
        self.profile.name()
    }

    /// Bytes of one lidar packet (other sizes are IMU or foreign packets).
    pub fn packet_size(&self) -> usize {
        self.header + self.columns_per_packet * self.column_size() + self.footer
    }

    /// An empty frame of this format.
    pub fn new_frame(&self, frame_id: u32) -> RawFrame {
        RawFrame::new(frame_id, self.rows, self.cols, self.profile.returns())
    }

    /// The frame id of a lidar packet (of the packet size).
    pub fn frame_id(&self, p: &[u8]) -> u32 {
        match self.profile {
            UdpProfile::Legacy => u32::from(le16(p, 10)),
            _ => u32::from(le16(p, 2)),
        }
    }

    /// `(initialisation id, serial number)` from the packet header; `None` for LEGACY
    /// packets, which carry neither.
    pub fn identity(&self, p: &[u8]) -> Option<(u32, u64)> {
        if self.profile == UdpProfile::Legacy {
            return None;
        }
        let init_id = u32::from_le_bytes([p[4], p[5], p[6], 0]);
        let mut sn = [0u8; 8];
        sn[..5].copy_from_slice(&p[7..12]);
        Some((init_id, u64::from_le_bytes(sn)))
    }

    /// Copies the packet's columns into `frame`. Columns with an invalid status or a
    /// measurement id outside the frame are skipped, as ouster-sdk does.
    pub fn decode_into(&self, p: &[u8], frame: &mut RawFrame) {
        let size = self.column_size();
        let columns = p[self.header..]
            .chunks_exact(size)
            .take(self.columns_per_packet);
        for col in columns {
            let m = usize::from(le16(col, 8));
            let valid = match self.profile {
                UdpProfile::Legacy => le32(col, size - 4) == 0xFFFF_FFFF,
                _ => le16(col, 10) & 1 == 1,
            };
            if !valid {
                continue;
            }
            if m >= self.cols {
                frame.out_of_range_columns += 1;
                continue;
            }
            frame.column_ns[m] = le64(col, 0);
            frame.column_valid[m] = true;
            let pixels = &col[self.column_header..self.column_header + self.rows * self.pixel];
            self.decode_column(pixels, m, frame);
        }
    }

    /// The pixels of one column (`rows × pixel` bytes) into column `m` of `f` (contiguous,
    /// as the frame is column-major), one loop per
    /// profile so the per-pixel work has no branch.
    fn decode_column(&self, pixels: &[u8], m: usize, f: &mut RawFrame) {
        let base = m * self.rows;
        let px = pixels.chunks_exact(self.pixel).enumerate();
        match self.profile {
            UdpProfile::Legacy | UdpProfile::Rng19Rfl8Sig16Nir16 => {
                // Same layout; LEGACY's range field is 20 bits wide, RNG19's 19.
                let range_mask = if self.profile == UdpProfile::Legacy {
                    0x000F_FFFF
                } else {
                    0x0007_FFFF
                };
                for (r, px) in px {
                    let i = base + r;
                    f.range_mm[i] = le32(px, 0) & range_mask;
                    // 16 bits on the wire, of which ouster-sdk reads the low 8 (calibrated 0..255).
                    f.reflectivity[i] = u32::from(px[4]);
                    f.signal[i] = u32::from(le16(px, 6));
                    f.near_ir[i] = u32::from(le16(px, 8));
                }
            }
            UdpProfile::Rng19Rfl8Sig16Nir16Dual => {
                for (r, px) in px {
                    let i = base + r;
                    f.range_mm[i] = le32(px, 0) & 0x0007_FFFF;
                    f.reflectivity[i] = u32::from(px[3]);
                    f.range2_mm[i] = le32(px, 4) & 0x0007_FFFF;
                    f.reflectivity2[i] = u32::from(px[7]);
                    f.signal[i] = u32::from(le16(px, 8));
                    f.signal2[i] = u32::from(le16(px, 10));
                    f.near_ir[i] = u32::from(le16(px, 12));
                }
            }
            UdpProfile::Rng15Rfl8Nir8 => {
                for (r, px) in px {
                    let i = base + r;
                    f.range_mm[i] = u32::from(le16(px, 0) & 0x7FFF) * 8;
                    f.reflectivity[i] = u32::from(px[2]);
                    // 8 bits on the wire, scaled by 16 as ouster-sdk does (NEAR_IR shift -4).
                    f.near_ir[i] = u32::from(px[3]) << 4;
                }
            }
            UdpProfile::Other(_) => {}
        }
    }
}

fn le16(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}

fn le32(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn le64(b: &[u8], at: usize) -> u64 {
    let mut a = [0u8; 8];
    a.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(a)
}

#[cfg(test)]
mod tests {
    use super::RawFrame;

    #[test]
    fn a_reused_frame_equals_a_fresh_one_once_missing_columns_are_cleared() {
        let (rows, cols) = (4, 6);
        let mut used = RawFrame::new(7, rows, cols, 2);
        for (i, v) in used.range_mm.iter_mut().enumerate() {
            *v = i as u32 + 1;
        }
        used.signal2.fill(9);
        used.column_valid.fill(true);
        used.column_ns.fill(5);
        used.reuse(8);
        let mut fresh = RawFrame::new(8, rows, cols, 2);
        // Column 2 arrives in both; the others are missing.
        for f in [&mut used, &mut fresh] {
            f.column_valid[2] = true;
            f.column_ns[2] = 42;
            for r in 0..rows {
                f.range_mm[2 * rows + r] = 100 + r as u32;
                f.signal2[2 * rows + r] = 3;
            }
        }
        used.clear_missing_columns();
        assert_eq!(used, fresh);
    }
}
