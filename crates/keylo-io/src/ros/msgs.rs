//! The messages keylo reads, decoded without copying their data: `sensor_msgs/PointCloud2`,
//! `sensor_msgs/Image` and `std_msgs/String` (Ouster metadata), in ROS1 or CDR encoding.

use super::wire::{Encoding, WireReader};

/// A ROS message that cannot be decoded; the message names the field and what is wrong
/// (`point_step is 0`, `` `data` at byte 40: 12 bytes left, 96 declared``).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct DecodeError {
    message: String,
}

impl DecodeError {
    /// What is wrong.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl From<String> for DecodeError {
    fn from(message: String) -> Self {
        Self { message }
    }
}

/// `std_msgs/Header` (ROS1's `seq` is read and dropped).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Header<'a> {
    /// Stamp, nanoseconds since the epoch (or the source's clock).
    pub stamp_ns: i64,
    /// Coordinate frame.
    pub frame_id: &'a str,
}

impl<'a> Header<'a> {
    fn read(r: &mut WireReader<'a>, encoding: Encoding) -> Result<Self, String> {
        let sec = match encoding {
            Encoding::Ros1 => {
                r.u32("header.seq")?;
                i64::from(r.u32("header.stamp.sec")?)
            }
            Encoding::Cdr => i64::from(r.i32("header.stamp.sec")?),
        };
        let nsec = i64::from(r.u32("header.stamp.nanosec")?);
        Ok(Self {
            stamp_ns: sec * 1_000_000_000 + nsec,
            frame_id: r.string("header.frame_id")?,
        })
    }

    /// The stamp in seconds.
    pub fn stamp_s(&self) -> f64 {
        let sec = self.stamp_ns.div_euclid(1_000_000_000);
        let nsec = self.stamp_ns.rem_euclid(1_000_000_000);
        sec as f64 + nsec as f64 * 1e-9
    }
}

/// `sensor_msgs/PointField`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PointField<'a> {
    /// Field name, e.g. `x`, `intensity`, `t`.
    pub name: &'a str,
    /// Byte offset inside a point.
    pub offset: u32,
    /// `INT8 = 1` … `FLOAT64 = 8`.
    pub datatype: u8,
    /// Elements in the field (1 for scalars).
    pub count: u32,
}

/// `sensor_msgs/PointCloud2`, its point data borrowed from the message.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCloud2<'a> {
    /// Stamp and frame.
    pub header: Header<'a>,
    /// Rows (1 for an unorganised cloud).
    pub height: u32,
    /// Points per row.
    pub width: u32,
    /// The point layout.
    pub fields: Vec<PointField<'a>>,
    /// Byte order of `data`.
    pub is_bigendian: bool,
    /// Bytes per point.
    pub point_step: u32,
    /// Bytes per row.
    pub row_step: u32,
    /// The points, `height × row_step` bytes.
    pub data: &'a [u8],
    /// True when the cloud has no invalid points.
    pub is_dense: bool,
}

impl<'a> PointCloud2<'a> {
    /// Decodes a serialised message.
    pub fn decode(buf: &'a [u8], encoding: Encoding) -> Result<Self, DecodeError> {
        let mut r = WireReader::new(buf, encoding)?;
        let header = Header::read(&mut r, encoding)?;
        let height = r.u32("height")?;
        let width = r.u32("width")?;
        // A PointField takes at least 4 (name length) + 4 + 1 + 4 bytes.
        let n = r.seq_len("fields", 13)?;
        let mut fields = Vec::with_capacity(n);
        for _ in 0..n {
            fields.push(PointField {
                name: r.string("fields[].name")?,
                offset: r.u32("fields[].offset")?,
                datatype: r.u8("fields[].datatype")?,
                count: r.u32("fields[].count")?,
            });
        }
        Ok(Self {
            header,
            height,
            width,
            fields,
            is_bigendian: r.u8("is_bigendian")? != 0,
            point_step: r.u32("point_step")?,
            row_step: r.u32("row_step")?,
            data: r.bytes("data")?,
            is_dense: r.u8("is_dense")? != 0,
        })
    }
}

/// `sensor_msgs/Image`, its pixels borrowed from the message.
#[derive(Debug, Clone, PartialEq)]
pub struct Image<'a> {
    /// Stamp and frame.
    pub header: Header<'a>,
    /// Rows.
    pub height: u32,
    /// Pixels per row.
    pub width: u32,
    /// Pixel encoding, e.g. `mono16`.
    pub encoding: &'a str,
    /// Byte order of multi-byte pixels.
    pub is_bigendian: bool,
    /// Bytes per row.
    pub step: u32,
    /// The pixels, `height × step` bytes.
    pub data: &'a [u8],
}

impl<'a> Image<'a> {
    /// Decodes a serialised message.
    pub fn decode(buf: &'a [u8], encoding: Encoding) -> Result<Self, DecodeError> {
        let mut r = WireReader::new(buf, encoding)?;
        Ok(Self {
            header: Header::read(&mut r, encoding)?,
            height: r.u32("height")?,
            width: r.u32("width")?,
            encoding: r.string("encoding")?,
            is_bigendian: r.u8("is_bigendian")? != 0,
            step: r.u32("step")?,
            data: r.bytes("data")?,
        })
    }
}

/// The header of a message that starts with one (PointCloud2, Image), without decoding the
/// rest: images are matched to clouds by stamp before either is decoded.
pub fn decode_header(buf: &[u8], encoding: Encoding) -> Result<Header<'_>, DecodeError> {
    let mut r = WireReader::new(buf, encoding)?;
    Ok(Header::read(&mut r, encoding)?)
}

/// The text of a `std_msgs/String`.
pub(crate) fn decode_string(buf: &[u8], encoding: Encoding) -> Result<&str, String> {
    WireReader::new(buf, encoding)?.string("data")
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Writes messages in either encoding (test messages only).
    pub struct Writer {
        pub buf: Vec<u8>,
        cdr: bool,
    }

    impl Writer {
        pub fn new(encoding: Encoding) -> Self {
            let cdr = encoding == Encoding::Cdr;
            let buf = if cdr { vec![0, 1, 0, 0] } else { Vec::new() };
            Self { buf, cdr }
        }
        fn pad(&mut self, a: usize) {
            if self.cdr {
                while !(self.buf.len() - 4).is_multiple_of(a) {
                    self.buf.push(0);
                }
            }
        }
        pub fn u8(&mut self, v: u8) -> &mut Self {
            self.buf.push(v);
            self
        }
        pub fn u32(&mut self, v: u32) -> &mut Self {
            self.pad(4);
            self.buf.extend_from_slice(&v.to_le_bytes());
            self
        }
        pub fn string(&mut self, s: &str) -> &mut Self {
            let extra = usize::from(self.cdr);
            self.u32((s.len() + extra) as u32);
            self.buf.extend_from_slice(s.as_bytes());
            if self.cdr {
                self.buf.push(0);
            }
            self
        }
        pub fn bytes(&mut self, b: &[u8]) -> &mut Self {
            self.u32(b.len() as u32);
            self.buf.extend_from_slice(b);
            self
        }
        pub fn header(&mut self, stamp_ns: i64) -> &mut Self {
            if !self.cdr {
                self.u32(0);
            }
            self.u32((stamp_ns / 1_000_000_000) as u32);
            self.u32((stamp_ns % 1_000_000_000) as u32);
            self.string("lidar")
        }
    }

    /// A serialised PointCloud2 with `(name, offset, datatype)` fields.
    pub fn cloud_msg(
        encoding: Encoding,
        stamp_ns: i64,
        (height, width, point_step): (u32, u32, u32),
        fields: &[(&str, u32, u8)],
        big_endian: bool,
        data: &[u8],
    ) -> Vec<u8> {
        let mut w = Writer::new(encoding);
        w.header(stamp_ns).u32(height).u32(width);
        w.u32(fields.len() as u32);
        for (name, offset, datatype) in fields {
            w.string(name).u32(*offset).u8(*datatype).u32(1);
        }
        w.u8(u8::from(big_endian));
        w.u32(point_step).u32(point_step * width).bytes(data).u8(1);
        w.buf
    }

    #[test]
    fn pointcloud2_in_both_encodings() {
        for enc in [Encoding::Ros1, Encoding::Cdr] {
            let data = [0u8; 24];
            let buf = cloud_msg(enc, 5_000_000_001, (1, 2, 12), &[("x", 0, 7)], false, &data);
            let m = PointCloud2::decode(&buf, enc).unwrap();
            assert_eq!(m.header.stamp_ns, 5_000_000_001);
            assert_eq!(m.header.frame_id, "lidar");
            assert_eq!(
                (m.height, m.width, m.point_step, m.row_step),
                (1, 2, 12, 24)
            );
            assert_eq!(m.fields[0].name, "x");
            assert_eq!(m.data.len(), 24);
            assert!(m.is_dense);
            assert!((m.header.stamp_s() - 5.000000001).abs() < 1e-12);
            let e = PointCloud2::decode(&buf[..buf.len() - 10], enc).unwrap_err();
            assert!(e.message().contains("`data`"), "{e}");
        }
    }

    #[test]
    fn image_and_string() {
        let mut w = Writer::new(Encoding::Cdr);
        w.header(7)
            .u32(1)
            .u32(2)
            .string("mono8")
            .u8(0)
            .u32(2)
            .bytes(&[3, 4]);
        let img = Image::decode(&w.buf, Encoding::Cdr).unwrap();
        assert_eq!(
            (img.encoding, img.step, img.data),
            ("mono8", 2, &[3u8, 4][..])
        );
        assert_eq!(decode_header(&w.buf, Encoding::Cdr).unwrap().stamp_ns, 7);
        let mut w = Writer::new(Encoding::Ros1);
        w.string("{\"a\": 1}");
        assert_eq!(decode_string(&w.buf, Encoding::Ros1).unwrap(), "{\"a\": 1}");
    }
}
