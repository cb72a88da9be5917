//! The run's fixed channels (the images' are made as images appear).

use std::sync::Arc;

use foxglove::messages::{FrameTransform, PointCloud, PoseInFrame, PosesInFrame};
use foxglove::{Channel, Context, RawChannel, Schema};

use crate::topics;
use crate::ViewError;

pub struct Channels {
    pub scan: Arc<RawChannel>,
    pub registered: Channel<PointCloud>,
    pub map: Channel<PointCloud>,
    pub pose: Channel<PoseInFrame>,
    pub tf: Channel<FrameTransform>,
    pub trajectory: Channel<PosesInFrame>,
    pub reference: Channel<PosesInFrame>,
    pub stats: Arc<RawChannel>,
}

impl Channels {
    pub fn new(ctx: &Arc<Context>) -> Result<Self, ViewError> {
        let raw = |topic: &str, encoding: &str, schema: Schema| {
            ctx.channel_builder(topic)
                .message_encoding(encoding)
                .schema(schema)
                .build_raw()
                .map_err(|e| ViewError::Channel {
                    topic: topic.to_string(),
                    message: e.to_string(),
                })
        };
        Ok(Self {
            scan: raw(
                topics::SCAN,
                "cdr",
                Schema::new(
                    "sensor_msgs/msg/PointCloud2",
                    "ros2msg",
                    crate::scan_cdr::POINTCLOUD2_SCHEMA.as_bytes(),
                ),
            )?,
            registered: ctx.channel_builder(topics::REGISTERED).build(),
            map: ctx.channel_builder(topics::MAP).build(),
            pose: ctx.channel_builder(topics::POSE).build(),
            tf: ctx.channel_builder(topics::TF).build(),
            trajectory: ctx.channel_builder(topics::TRAJECTORY).build(),
            reference: ctx.channel_builder(topics::REFERENCE).build(),
            stats: raw(
                topics::STATS,
                "json",
                Schema::new(
                    "keylo.FrameStats",
                    "jsonschema",
                    crate::stats::SCHEMA.as_bytes(),
                ),
            )?,
        })
    }

    /// Whether a live client subscribed to any of them.
    pub fn any_subscribed(&self) -> bool {
        self.scan.has_sinks()
            || self.registered.has_sinks()
            || self.map.has_sinks()
            || self.pose.has_sinks()
            || self.tf.has_sinks()
            || self.stats.has_sinks()
    }
}
