//! Errors of the ROS 2 node.

/// What can stop the node from starting or running (a bad message never does: it is logged
/// and skipped).
#[derive(Debug, thiserror::Error)]
pub enum Ros2Error {
    /// A `[ros2]` setting is wrong.
    #[error("{origin}: {message}")]
    Config { origin: String, message: String },
    /// The DDS participant, a topic, a reader or a writer could not be made.
    #[error("DDS: {0}")]
    Dds(String),
    /// keylo's pipeline failed in a way the node cannot go on from.
    #[error(transparent)]
    Core(#[from] keylo_core::CoreError),
}
