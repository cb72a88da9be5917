//! The DDS side of the node: one participant, the node's topics, its writers, and a thread
//! that reads every input topic and hands clouds to the [`Inbox`] and commands to a channel.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use ros2_client::dds::rustdds::mio1::{Events, Interest, Poll, Token};
use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::{
    Context, ContextOptions, MessageTypeName, Name, Node, NodeName, NodeOptions, Publisher,
    QosProfile, Subscription,
};
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::config::{self, Ros2Config};
use crate::inbox::Inbox;
use crate::msgs::{self, RosMessage};
use crate::Ros2Error;

/// A command from a control topic.
#[derive(Debug, Clone)]
pub enum Command {
    Reset,
    SetPose(Box<msgs::PoseWithCovarianceStamped>),
    MotionPrior(Box<msgs::Odometry>),
}

/// The node's writers (`None`: the topic is off).
pub struct Writers {
    pub odometry: Publisher<msgs::Odometry>,
    pub tf: Option<Publisher<msgs::TfMessage>>,
    pub path: Option<Publisher<msgs::Path>>,
    pub registered_cloud: Option<Publisher<msgs::PointCloud2>>,
    pub keypoint_cloud: Option<Publisher<msgs::PointCloud2>>,
    pub local_map: Option<Publisher<msgs::PointCloud2>>,
    pub keypoint_image: Option<Publisher<msgs::Image>>,
}

/// A running DDS participant with the node's topics.
///
/// Fields drop in order: the writers, then (after `Drop` joined the reader thread, which owns
/// the readers) the node, then the participant, so RustDDS removes every endpoint before its
/// event loop stops.
pub struct Dds {
    pub writers: Writers,
    /// Clouds with the instant the reader took them from DDS.
    pub inbox: Arc<Inbox<(Instant, msgs::PointCloud2)>>,
    pub commands: mpsc::Receiver<Command>,
    /// Input messages that could not be decoded as their type (counted, logged).
    pub undecodable: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
    _node: Node,
    _context: Context,
}

/// Reliable, keep last `depth` (tf2 listens to `/tf` with depth 100).
fn reliable(depth: usize) -> QosProfile {
    QosProfile::publisher_default()
        .reliability_reliable(WhenFull::DEFAULT)
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth })
}

/// ROS 2's sensor-data profile: best effort, keep last 5.
fn sensor_data() -> QosProfile {
    QosProfile::subscription_default()
        .reliability(Reliability::BestEffort)
        .history(History::KeepLast { depth: 5 })
}

/// `topic` resolved in `namespace` (a relative name gets the namespace in front).
pub fn resolve(namespace: &str, topic: &str) -> String {
    if topic.starts_with('/') {
        topic.to_string()
    } else {
        format!("{}/{topic}", namespace.trim_end_matches('/'))
    }
}

impl Dds {
    /// Joins the DDS domain and makes the node's topics.
    pub fn start(config: &Ros2Config) -> Result<Self, Ros2Error> {
        let dds = |what: &str, e: &dyn std::fmt::Display| Ros2Error::Dds(format!("{what}: {e}"));
        let domain = config.domain()?;
        let context = Context::with_options(ContextOptions::new().domain_id(domain))
            .map_err(|e| dds(&format!("joining domain {domain}"), &e))?;
        let namespace = config.namespace_path();
        let mut node = context
            .new_node(
                NodeName::new(&namespace, &config.node_name).map_err(|e| Ros2Error::Config {
                    origin: "ros2.node_name / ros2.namespace".into(),
                    message: format!("`{namespace}` `{}`: {e:?}", config.node_name),
                })?,
                NodeOptions::new().enable_rosout(false),
            )
            .map_err(|e| dds("creating the node", &e))?;
        let ns = namespace.as_str();
        let mut make = Maker {
            node: &mut node,
            ns,
        };
        let writers = Writers {
            odometry: make.writer(&config.odometry_topic, "odometry_topic", reliable(100))?,
            tf: if config.publish_odom_tf {
                Some(make.writer("/tf", "publish_odom_tf", reliable(100))?)
            } else {
                None
            },
            path: make.optional_writer(&config.path_topic, "path_topic")?,
            registered_cloud: make
                .optional_writer(&config.registered_cloud_topic, "registered_cloud_topic")?,
            keypoint_cloud: make
                .optional_writer(&config.keypoint_cloud_topic, "keypoint_cloud_topic")?,
            local_map: make.optional_writer(&config.local_map_topic, "local_map_topic")?,
            keypoint_image: make
                .optional_writer(&config.keypoint_image_topic, "keypoint_image_topic")?,
        };
        let input_qos = match config.input_reliability {
            config::Reliability::BestEffort => sensor_data(),
            config::Reliability::Reliable => reliable(100),
        };
        let points: Subscription<msgs::PointCloud2> =
            make.reader(&config.points_topic, "points_topic", input_qos)?;
        let reset = make.optional_reader::<msgs::Empty>(&config.reset_topic, "reset_topic")?;
        let set_pose = make.optional_reader::<msgs::PoseWithCovarianceStamped>(
            &config.set_pose_topic,
            "set_pose_topic",
        )?;
        let prior = make
            .optional_reader::<msgs::Odometry>(&config.motion_prior_topic, "motion_prior_topic")?;
        let inbox = Arc::new(Inbox::new(config.max_pending_clouds));
        let (tx, commands) = mpsc::channel();
        let stop = Arc::new(AtomicBool::new(false));
        let undecodable = Arc::new(AtomicU64::new(0));
        let readers = Readers {
            points: (points, config.topic(&config.points_topic)),
            reset: reset.map(|r| (r, config.topic(&config.reset_topic))),
            set_pose: set_pose.map(|r| (r, config.topic(&config.set_pose_topic))),
            prior: prior.map(|r| (r, config.topic(&config.motion_prior_topic))),
        };
        let reader = {
            let (inbox, stop, undecodable) = (
                Arc::clone(&inbox),
                Arc::clone(&stop),
                Arc::clone(&undecodable),
            );
            std::thread::Builder::new()
                .name("keylo-ros2-reader".into())
                .spawn(move || readers.run(&inbox, &tx, &stop, &undecodable))
                .map_err(|e| dds("starting the reader thread", &e))?
        };
        Ok(Self {
            writers,
            inbox,
            commands,
            undecodable,
            stop,
            reader: Some(reader),
            _node: node,
            _context: context,
        })
    }
}

impl Drop for Dds {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(h) = self.reader.take() {
            let _ = h.join();
        }
    }
}

/// Makes topics, writers and readers of one node.
struct Maker<'a> {
    node: &'a mut Node,
    ns: &'a str,
}

impl Maker<'_> {
    fn topic<M: RosMessage>(
        &mut self,
        topic: &str,
        key: &str,
        qos: &QosProfile,
    ) -> Result<ros2_client::dds::rustdds::Topic, Ros2Error> {
        let full = resolve(self.ns, topic);
        let name = Name::parse(&full).map_err(|e| Ros2Error::Config {
            origin: format!("ros2.{key}"),
            message: format!("`{topic}` is not a valid ROS 2 topic name ({e:?})"),
        })?;
        self.node
            .create_topic(&name, MessageTypeName::new(M::PACKAGE, M::NAME), qos)
            .map_err(|e| Ros2Error::Dds(format!("topic {full}: {e}")))
    }

    fn writer<M: RosMessage + Serialize>(
        &mut self,
        topic: &str,
        key: &str,
        qos: QosProfile,
    ) -> Result<Publisher<M>, Ros2Error> {
        let t = self.topic::<M>(topic, key, &qos)?;
        self.node
            .create_publisher(&t, Some(qos))
            .map_err(|e| Ros2Error::Dds(format!("writer of {topic}: {e}")))
    }

    fn optional_writer<M: RosMessage + Serialize>(
        &mut self,
        topic: &str,
        key: &str,
    ) -> Result<Option<Publisher<M>>, Ros2Error> {
        if topic.is_empty() {
            return Ok(None);
        }
        self.writer(topic, key, reliable(10)).map(Some)
    }

    fn reader<M: RosMessage + 'static>(
        &mut self,
        topic: &str,
        key: &str,
        qos: QosProfile,
    ) -> Result<Subscription<M>, Ros2Error> {
        let t = self.topic::<M>(topic, key, &qos)?;
        self.node
            .create_subscription(&t, Some(qos))
            .map_err(|e| Ros2Error::Dds(format!("reader of {topic}: {e}")))
    }

    fn optional_reader<M: RosMessage + 'static>(
        &mut self,
        topic: &str,
        key: &str,
    ) -> Result<Option<Subscription<M>>, Ros2Error> {
        if topic.is_empty() {
            return Ok(None);
        }
        self.reader(topic, key, reliable(10)).map(Some)
    }
}

/// The input readers with their topic names, moved into the reader thread.
struct Readers {
    points: (Subscription<msgs::PointCloud2>, String),
    reset: Option<(Subscription<msgs::Empty>, String)>,
    set_pose: Option<(Subscription<msgs::PoseWithCovarianceStamped>, String)>,
    prior: Option<(Subscription<msgs::Odometry>, String)>,
}

/// Every reader wakes the poll alike: whatever arrived, all readers are drained.
const ANY: Token = Token(0);

impl Readers {
    fn run(
        mut self,
        inbox: &Inbox<(Instant, msgs::PointCloud2)>,
        commands: &mpsc::Sender<Command>,
        stop: &AtomicBool,
        undecodable: &AtomicU64,
    ) {
        let mut poll = match Poll::new() {
            Ok(p) => p,
            Err(e) => {
                tracing::error!("ros2: cannot poll the DDS readers: {e}; no input will be read");
                return;
            }
        };
        let registry = poll.registry();
        let mut ok = registry
            .register(&mut self.points.0, ANY, Interest::READABLE)
            .is_ok();
        if let Some((r, _)) = self.reset.as_mut() {
            ok &= registry.register(r, ANY, Interest::READABLE).is_ok();
        }
        if let Some((r, _)) = self.set_pose.as_mut() {
            ok &= registry.register(r, ANY, Interest::READABLE).is_ok();
        }
        if let Some((r, _)) = self.prior.as_mut() {
            ok &= registry.register(r, ANY, Interest::READABLE).is_ok();
        }
        if !ok {
            tracing::error!("ros2: cannot register the DDS readers; no input will be read");
            return;
        }
        let mut events = Events::with_capacity(16);
        while !stop.load(Ordering::SeqCst) {
            if let Err(e) = poll.poll(&mut events, Some(Duration::from_millis(100))) {
                if e.kind() != std::io::ErrorKind::Interrupted {
                    tracing::warn!("ros2: polling the DDS readers: {e}");
                }
            }
            // Edge-triggered: drain every reader whenever anything arrived (cheap when empty).
            let (points, topic) = &self.points;
            drain(points, topic, undecodable, |m| {
                if inbox.push((Instant::now(), m)) {
                    tracing::debug!("{topic}: registration is behind; dropped the oldest cloud");
                }
            });
            if let Some((r, topic)) = &self.reset {
                drain(r, topic, undecodable, |_| {
                    let _ = commands.send(Command::Reset);
                });
            }
            if let Some((r, topic)) = &self.set_pose {
                drain(r, topic, undecodable, |m| {
                    let _ = commands.send(Command::SetPose(Box::new(m)));
                });
            }
            if let Some((r, topic)) = &self.prior {
                drain(r, topic, undecodable, |m| {
                    let _ = commands.send(Command::MotionPrior(Box::new(m)));
                });
            }
        }
    }
}

/// Takes every waiting message of `reader`; one that does not decode as its type is logged
/// with its topic and counted, and reading goes on.
fn drain<M: DeserializeOwned + 'static>(
    reader: &Subscription<M>,
    topic: &str,
    undecodable: &AtomicU64,
    mut each: impl FnMut(M),
) {
    // Bounded, so a reader that keeps failing cannot hold the thread.
    for _ in 0..10_000 {
        match reader.take() {
            Ok(Some((m, _info))) => each(m),
            Ok(None) => return,
            Err(e) => {
                undecodable.fetch_add(1, Ordering::Relaxed);
                tracing::warn!("{topic}: a message could not be decoded ({e:?}); skipped");
            }
        }
    }
}
