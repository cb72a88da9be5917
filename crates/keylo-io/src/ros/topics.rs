//! Topics of a file (channels grouped by name) and the choice of the ones a source reads.

use super::file::{normalise_type, ChannelInfo};
use super::wire::Encoding;

/// The PointCloud2 message type (ROS1 spelling; ROS2's `sensor_msgs/msg/…` compares equal).
pub(crate) const POINTCLOUD2: &str = "sensor_msgs/PointCloud2";
/// The Image message type.
pub(crate) const IMAGE: &str = "sensor_msgs/Image";
/// The String message type (Ouster metadata).
pub(crate) const STRING: &str = "std_msgs/String";

/// One topic: every channel (connection) stored under its name.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Topic {
    pub name: String,
    /// Message type as stored (of the first channel).
    pub msg_type: String,
    /// Encoding as stored (of the first channel).
    pub encoding_name: String,
    /// `None` when keylo cannot decode it, or the channels disagree.
    pub encoding: Option<Encoding>,
    pub ids: Vec<u32>,
    /// Messages on all channels, when the file says.
    pub count: Option<u64>,
}

impl Topic {
    /// Whether the topic holds messages of `ty` (ROS1 or ROS2 spelling).
    pub fn is(&self, ty: &str) -> bool {
        normalise_type(&self.msg_type) == normalise_type(ty)
    }

    /// `name (type, N messages)` for error messages and listings.
    pub fn describe(&self) -> String {
        let count = self
            .count
            .map_or("unknown count".to_string(), |n| format!("{n} messages"));
        format!("{} ({}, {count})", self.name, self.msg_type)
    }
}

/// The topics of a file in name order.
pub(crate) fn topics(channels: &[ChannelInfo]) -> Vec<Topic> {
    let mut out: Vec<Topic> = Vec::new();
    for c in channels {
        match out.iter_mut().find(|t| t.name == c.topic) {
            Some(t) => {
                t.ids.push(c.id);
                t.count = t.count.zip(c.count).map(|(a, b)| a + b);
                if t.encoding != c.encoding || !t.is(&c.msg_type) {
                    t.encoding = None;
                }
            }
            None => out.push(Topic {
                name: c.topic.clone(),
                msg_type: c.msg_type.clone(),
                encoding_name: c.encoding_name.clone(),
                encoding: c.encoding,
                ids: vec![c.id],
                count: c.count,
            }),
        }
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

fn list(topics: &[&Topic]) -> String {
    let items: Vec<String> = topics.iter().map(|t| t.describe()).collect();
    items.join(", ")
}

/// The PointCloud2 topic to read: `wanted`, or the only one when `wanted` is empty.
pub(crate) fn cloud_topic<'a>(all: &'a [Topic], wanted: &str) -> Result<&'a Topic, String> {
    let clouds: Vec<&Topic> = all.iter().filter(|t| t.is(POINTCLOUD2)).collect();
    let everything: Vec<&Topic> = all.iter().collect();
    if wanted.is_empty() {
        return match clouds.as_slice() {
            [one] => checked(one, POINTCLOUD2, "source.topic"),
            [] => Err(format!(
                "the file has no sensor_msgs/PointCloud2 topic; it holds: {}",
                list(&everything)
            )),
            many => Err(format!(
                "the file has {} sensor_msgs/PointCloud2 topics: set `source.topic` to one of: {}",
                many.len(),
                list(many)
            )),
        };
    }
    match all.iter().find(|t| t.name == wanted) {
        Some(t) => checked(t, POINTCLOUD2, "source.topic"),
        None if clouds.is_empty() => Err(format!(
            "no topic `{wanted}`, and no sensor_msgs/PointCloud2 topic at all; the file holds: {}",
            list(&everything)
        )),
        None => Err(format!(
            "no topic `{wanted}`; set `source.topic` to one of: {}",
            list(&clouds)
        )),
    }
}

/// The topic `name` of type `ty` (for image and metadata topics); `key` names the config key.
pub(crate) fn typed_topic<'a>(
    all: &'a [Topic],
    name: &str,
    ty: &str,
    key: &str,
) -> Result<&'a Topic, String> {
    match all.iter().find(|t| t.name == name) {
        Some(t) => checked(t, ty, key),
        None => {
            let same: Vec<&Topic> = all.iter().filter(|t| t.is(ty)).collect();
            Err(format!(
                "`{key}` = \"{name}\": no such topic; {ty} topics: {}",
                if same.is_empty() {
                    "none".to_string()
                } else {
                    list(&same)
                }
            ))
        }
    }
}

fn checked<'a>(t: &'a Topic, ty: &str, key: &str) -> Result<&'a Topic, String> {
    if !t.is(ty) {
        return Err(format!(
            "`{key}`: topic {} holds {}, expected {ty}",
            t.name, t.msg_type
        ));
    }
    if t.encoding.is_none() {
        return Err(format!(
            "`{key}`: topic {} has message encoding `{}`; keylo reads `ros1` and `cdr`",
            t.name, t.encoding_name
        ));
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ch(id: u32, topic: &str, ty: &str, count: u64) -> ChannelInfo {
        ChannelInfo {
            id,
            topic: topic.into(),
            msg_type: ty.into(),
            encoding: Some(Encoding::Cdr),
            encoding_name: "cdr".into(),
            count: Some(count),
        }
    }

    #[test]
    fn choosing_the_cloud_topic() {
        let pc = "sensor_msgs/msg/PointCloud2";
        let one = topics(&[ch(1, "/p", pc, 3), ch(2, "/i", "sensor_msgs/msg/Image", 3)]);
        assert_eq!(cloud_topic(&one, "").unwrap().name, "/p");
        let two = topics(&[ch(1, "/p", pc, 3), ch(2, "/q", pc, 4), ch(3, "/p", pc, 2)]);
        assert_eq!(two[0].ids, vec![1, 3]);
        assert_eq!(two[0].count, Some(5));
        let e = cloud_topic(&two, "").unwrap_err();
        assert!(e.contains("set `source.topic` to one of:"), "{e}");
        assert!(
            e.contains("/p (sensor_msgs/msg/PointCloud2, 5 messages)")
                && e.contains("/q (sensor_msgs/msg/PointCloud2, 4 messages)"),
            "{e}"
        );
        assert_eq!(cloud_topic(&two, "/q").unwrap().name, "/q");
        let e = cloud_topic(&two, "/missing").unwrap_err();
        assert!(
            e.contains("no topic `/missing`") && e.contains("/q ("),
            "{e}"
        );
        let e = cloud_topic(&one, "/i").unwrap_err();
        assert!(e.contains("holds sensor_msgs/msg/Image"), "{e}");
        let none = topics(&[ch(2, "/i", "sensor_msgs/msg/Image", 3)]);
        assert!(cloud_topic(&none, "")
            .unwrap_err()
            .contains("no sensor_msgs/PointCloud2"));
    }

    #[test]
    fn typed_topics_and_encodings() {
        let mut c = ch(1, "/img", "sensor_msgs/Image", 1);
        let all = topics(std::slice::from_ref(&c));
        assert!(typed_topic(&all, "/img", IMAGE, "k").is_ok());
        let e = typed_topic(&all, "/x", IMAGE, "source.images.signal").unwrap_err();
        assert!(
            e.contains("source.images.signal") && e.contains("/img ("),
            "{e}"
        );
        c.encoding = None;
        c.encoding_name = "protobuf".into();
        let all = topics(&[c]);
        let e = typed_topic(&all, "/img", IMAGE, "k").unwrap_err();
        assert!(e.contains("protobuf"), "{e}");
    }
}
