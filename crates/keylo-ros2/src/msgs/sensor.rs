//! `sensor_msgs/PointCloud2` (in and out) and `sensor_msgs/Image` (out).

use serde::{Deserialize, Serialize};

use super::Header;

/// `sensor_msgs/PointField`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct PointField {
    pub name: String,
    pub offset: u32,
    /// `INT8 = 1` … `FLOAT64 = 8`.
    pub datatype: u8,
    pub count: u32,
}

/// `sensor_msgs/PointCloud2`; `data` is read and written in one copy (`serde_bytes`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PointCloud2 {
    pub header: Header,
    pub height: u32,
    pub width: u32,
    pub fields: Vec<PointField>,
    pub is_bigendian: bool,
    pub point_step: u32,
    pub row_step: u32,
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
    pub is_dense: bool,
}

impl PointCloud2 {
    /// keylo-io's borrowed view of this message, for its decoder.
    pub fn view(&self) -> keylo_io::ros::PointCloud2<'_> {
        keylo_io::ros::PointCloud2 {
            header: keylo_io::ros::Header {
                stamp_ns: self.header.stamp.to_ns(),
                frame_id: &self.header.frame_id,
            },
            height: self.height,
            width: self.width,
            fields: self
                .fields
                .iter()
                .map(|f| keylo_io::ros::PointField {
                    name: &f.name,
                    offset: f.offset,
                    datatype: f.datatype,
                    count: f.count,
                })
                .collect(),
            is_bigendian: self.is_bigendian,
            point_step: self.point_step,
            row_step: self.row_step,
            data: &self.data,
            is_dense: self.is_dense,
        }
    }

    /// An unorganised cloud of `x y z` (float32) points, one field per extra channel.
    pub fn xyz(header: Header, points: &[[f32; 3]], extra: &[(&str, &[f32])]) -> Self {
        let names = ["x", "y", "z"]
            .into_iter()
            .chain(extra.iter().map(|(n, _)| *n));
        let fields: Vec<PointField> = names
            .enumerate()
            .map(|(i, name)| PointField {
                name: name.to_string(),
                offset: 4 * i as u32,
                datatype: 7,
                count: 1,
            })
            .collect();
        let step = 4 * fields.len();
        let mut data = Vec::with_capacity(points.len() * step);
        for (i, p) in points.iter().enumerate() {
            for v in p {
                data.extend_from_slice(&v.to_le_bytes());
            }
            for (_, values) in extra {
                let v = values.get(i).copied().unwrap_or(0.0);
                data.extend_from_slice(&v.to_le_bytes());
            }
        }
        Self {
            header,
            height: 1,
            width: points.len() as u32,
            fields,
            is_bigendian: false,
            point_step: step as u32,
            row_step: (step * points.len()) as u32,
            data,
            is_dense: true,
        }
    }
}

/// `sensor_msgs/Image`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Image {
    pub header: Header,
    pub height: u32,
    pub width: u32,
    pub encoding: String,
    pub is_bigendian: u8,
    pub step: u32,
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
}
