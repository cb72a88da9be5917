//! Parameters of source kinds `ros1-bag` and `mcap` (one struct: the kinds differ only in the
//! file format they accept).

use serde::{Deserialize, Serialize};

use crate::cloud::ProjectionConfig;

/// `[source] kind = "ros1-bag"` or `kind = "mcap"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct BagSourceConfig {
    /// The recording: a `.bag` file (`ros1-bag`), or an `.mcap` file, a ROS2 sqlite3 `.db3` file
    /// or a ROS2 bag folder holding one of them (`mcap`); relative to the config file.
    pub path: String,
    /// The sensor_msgs/PointCloud2 topic to read; empty = the file's only PointCloud2 topic.
    pub topic: String,
    /// Index of the first cloud to read (clouds of the topic counted from 0 in log-time order).
    pub start: usize,
    /// Read every `stride`-th cloud from `start` (1 = every cloud).
    pub stride: usize,
    /// Clouds to read at most; 0 = all.
    pub max_frames: usize,
    /// std_msgs/String topic with the Ouster sensor metadata JSON (ouster-ros records it):
    /// gives the beam geometry of organised clouds and the column shift of image topics. Not
    /// used when the file has no such topic; empty = never.
    pub metadata_topic: String,
    /// `[source.images]`: sensor_msgs/Image topics filling channels of organised clouds.
    pub images: ImageTopics,
    /// `[source.projection]`: the image grid of unorganised clouds (height 1).
    pub projection: ProjectionConfig,
}

impl Default for BagSourceConfig {
    fn default() -> Self {
        Self {
            path: String::new(),
            topic: String::new(),
            start: 0,
            stride: 1,
            max_frames: 0,
            metadata_topic: "/ouster/metadata".into(),
            images: ImageTopics::default(),
            projection: ProjectionConfig::default(),
        }
    }
}

/// `[source.images]`: the image of each channel is the message of its topic whose header stamp
/// equals the cloud's, to the nanosecond; a frame without one is an error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ImageTopics {
    /// Topic of the signal channel (e.g. `/ouster/signal_image`); empty = the cloud's
    /// intensity field.
    pub signal: String,
    /// Topic of the reflectivity channel (e.g. `/ouster/reflec_image`); empty = the cloud's
    /// field.
    pub reflectivity: String,
    /// Topic of the near-IR channel (e.g. `/ouster/nearir_image`); empty = the cloud's
    /// ambient field.
    pub near_ir: String,
    /// Topic of the range channel (e.g. `/ouster/range_image`), pixel × `range_unit_m`
    /// metres; it replaces the range channel only (points and validity stay the cloud's).
    /// Empty = the cloud's range.
    pub range: String,
    /// Metres per range-image unit: 0.004 for ouster-ros' mono16 range images (4 mm).
    pub range_unit_m: f64,
    /// Column shift per row from the cloud to the images: cloud pixel `(r, c)` is image pixel
    /// `(r, (c + shift[r]) mod cols)`. One entry applies to every row; `[0]` = same layout.
    /// Empty = automatic: 0 for destaggered clouds (newer ouster-ros), the sensor's
    /// `pixel_shift_by_row` from `metadata_topic` for staggered ones (a cloud is staggered
    /// when all points of a column share one time).
    pub pixel_shift_by_row: Vec<i64>,
}

impl Default for ImageTopics {
    fn default() -> Self {
        Self {
            signal: String::new(),
            reflectivity: String::new(),
            near_ir: String::new(),
            range: String::new(),
            range_unit_m: 0.004,
            pixel_shift_by_row: Vec::new(),
        }
    }
}

impl ImageTopics {
    /// `(channel, topic, config key)` of every topic set.
    pub(crate) fn selected(&self) -> Vec<(keylo_core::Channel, &str, &'static str)> {
        use keylo_core::Channel;
        [
            (Channel::Signal, &self.signal, "source.images.signal"),
            (
                Channel::Reflectivity,
                &self.reflectivity,
                "source.images.reflectivity",
            ),
            (Channel::NearIr, &self.near_ir, "source.images.near_ir"),
            (Channel::Range, &self.range, "source.images.range"),
        ]
        .into_iter()
        .filter(|(_, t, _)| !t.is_empty())
        .map(|(c, t, k)| (c, t.as_str(), k))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_unknown_keys() {
        let c: BagSourceConfig =
            toml::from_str("path = \"a.bag\"\n[images]\nsignal = \"/s\"").expect("parses");
        assert_eq!(c.stride, 1);
        assert_eq!(c.metadata_topic, "/ouster/metadata");
        assert_eq!(c.images.range_unit_m, 0.004);
        assert_eq!(c.images.selected().len(), 1);
        assert!(toml::from_str::<BagSourceConfig>("topics = \"x\"").is_err());
        assert!(toml::from_str::<BagSourceConfig>("[images]\nsignl = \"x\"").is_err());
    }
}
