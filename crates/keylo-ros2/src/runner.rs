//! The node's loop: take the newest waiting cloud, make it a frame as `keylo run` does for a
//! bag's clouds, register it, publish odometry, TF, path and the debug topics. A bad cloud is
//! a log line naming the topic, stamp and what is wrong, and the loop goes on.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use keylo_core::{FrameFeatures, FrameResult, LidarFrame, Odometry};
use keylo_io::cloud::{ProjectionConfig, Projector, Sensor};
use keylo_io::ros::CloudFramer;
use nalgebra::Isometry3;

use crate::dds::{resolve, Command, Dds};
use crate::frames::{self, BaseFrame};
use crate::msgs::{self, Time};
use crate::outputs::{self, OdometryParts, PathKeeper};
use crate::prior::PriorTrack;
use crate::{Ros2Config, Ros2Error};

/// What the node did, for the summary and the log.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct NodeStats {
    /// Clouds received on the points topic.
    pub clouds_received: u64,
    /// Clouds dropped because registration was behind (the oldest waiting one each time).
    pub clouds_dropped: u64,
    /// Clouds refused (bad layout, no finite point, time going backwards, another frame_id,
    /// a stage's error), each logged.
    pub clouds_refused: u64,
    /// Input messages that did not decode as their type.
    pub messages_undecodable: u64,
    /// Frames registered and published.
    pub frames: u64,
    /// Frames whose covariance was the fixed fallback (no estimate from the registrar).
    pub fallback_covariances: u64,
    /// Frames whose initial guess came from the motion prior topic.
    pub motion_priors_used: u64,
    /// Reset and set-pose commands carried out.
    pub resets: u64,
    pub poses_set: u64,
}

/// One registered frame, as the node published it.
pub struct Published<'a> {
    pub result: &'a FrameResult,
    /// The odometry message's stamp (the scan's end, on the cloud's clock), nanoseconds.
    pub stamp_ns: i64,
    /// Time spent in keylo's stages on this frame, seconds.
    pub seconds: f64,
    /// From the cloud taken from DDS (or the frame from the source) to its odometry published,
    /// seconds: waiting, decoding, the stages and publishing.
    pub in_node_seconds: f64,
}

/// The ROS 2 node: DDS in and out around an [`Odometry`].
pub struct Ros2Node {
    pub(crate) config: Ros2Config,
    pub(crate) dds: Dds,
    framer: CloudFramer,
    base: BaseFrame,
    points_topic: String,
    path: PathKeeper,
    prior: PriorTrack,
    /// The frame of the first cloud; later clouds must keep it.
    cloud_frame: Option<String>,
    /// The previous frame's published base pose and end stamp (s).
    previous: Option<(Isometry3<f64>, f64)>,
    /// The last frame's base pose before `anchor` (keylo's own, from the first scan).
    last_raw_base: Option<Isometry3<f64>>,
    /// Set by set-pose: published pose = anchor · keylo's base pose.
    anchor: Isometry3<f64>,
    next_index: u64,
    pub(crate) stats: NodeStats,
    want_features: bool,
    pending_prior: bool,
}

impl Ros2Node {
    /// Joins DDS and makes the topics of `config` for `odometry`'s pipeline.
    pub fn start(config: Ros2Config, odometry: &Odometry) -> Result<Self, Ros2Error> {
        let base = BaseFrame::new(frames::extrinsic(&config.base_to_lidar).map_err(|message| {
            Ros2Error::Config {
                origin: "config".into(),
                message,
            }
        })?);
        let projector = Projector::from_config(&ProjectionConfig::default(), Sensor::Generic)
            .map_err(|e| Ros2Error::Config {
                origin: "projection".into(),
                message: e.to_string(),
            })?;
        let mut framer = CloudFramer::new(projector, None, &config.points_topic);
        framer.set_grid_needed(odometry.needs_grid());
        let dds = Dds::start(&config)?;
        let points_topic = resolve(&config.namespace, &config.points_topic);
        tracing::info!(
            "ros2: listening on {points_topic} ({:?}), odometry on {}",
            config.input_reliability,
            resolve(&config.namespace, &config.odometry_topic)
        );
        Ok(Self {
            want_features: !config.keypoint_cloud_topic.is_empty()
                || !config.keypoint_image_topic.is_empty(),
            path: PathKeeper::new(config.path_max_poses),
            config,
            dds,
            framer,
            base,
            points_topic,
            prior: PriorTrack::default(),
            cloud_frame: None,
            previous: None,
            last_raw_base: None,
            anchor: Isometry3::identity(),
            next_index: 0,
            stats: NodeStats::default(),
            pending_prior: false,
        })
    }

    /// Runs until `stop` is set (Ctrl-C, SIGTERM) or `idle` passes without a cloud (when
    /// given), calling `on_frame` after each frame is published.
    pub fn run(
        &mut self,
        odometry: &mut Odometry,
        stop: &AtomicBool,
        idle: Option<Duration>,
        mut on_frame: impl FnMut(&Published),
    ) -> NodeStats {
        let mut last_input = Instant::now();
        while !stop.load(Ordering::SeqCst) {
            while let Ok(c) = self.dds.commands.try_recv() {
                self.command(odometry, c);
            }
            let Some((taken, msg)) = self.dds.inbox.pop(Duration::from_millis(50)) else {
                if idle.is_some_and(|d| last_input.elapsed() >= d) {
                    break;
                }
                continue;
            };
            last_input = Instant::now();
            self.cloud(odometry, &msg, taken, &mut on_frame);
        }
        self.stats()
    }

    /// The counts so far.
    pub fn stats(&self) -> NodeStats {
        let (received, dropped) = self.dds.inbox.counts();
        NodeStats {
            clouds_received: received,
            clouds_dropped: dropped,
            messages_undecodable: self.dds.undecodable.load(Ordering::Relaxed),
            ..self.stats.clone()
        }
    }

    pub(crate) fn command(&mut self, odometry: &mut Odometry, c: Command) {
        match c {
            Command::Reset => match odometry.reset() {
                Ok(()) => {
                    self.previous = None;
                    self.last_raw_base = None;
                    self.anchor = Isometry3::identity();
                    self.cloud_frame = None;
                    self.path.clear();
                    self.prior.clear();
                    self.stats.resets += 1;
                    tracing::info!("ros2: reset: map and motion forgotten");
                }
                Err(e) => tracing::warn!("ros2: reset refused: {e}"),
            },
            Command::SetPose(m) => {
                let Some(base) = frames::pose_from_msg(&m.pose.pose) else {
                    tracing::warn!(
                        "{}: pose is not finite or its quaternion is not unit length; ignored",
                        self.config.set_pose_topic
                    );
                    return;
                };
                if !m.header.frame_id.is_empty()
                    && m.header.frame_id != self.config.lidar_odom_frame
                {
                    tracing::warn!(
                        "{}: the pose is in `{}`, expected `{}`; ignored",
                        self.config.set_pose_topic,
                        m.header.frame_id,
                        self.config.lidar_odom_frame
                    );
                    return;
                }
                // The published odometry is re-anchored: the base is at `base` now and moves on
                // from there. keylo's own map and poses are left as they are, so registration
                // goes on against a consistent map.
                let raw = self.last_raw_base.unwrap_or_else(Isometry3::identity);
                self.anchor = base * raw.inverse();
                // The next twist would otherwise jump by the set-pose step.
                self.previous = self.previous.map(|(_, t)| (base, t));
                self.stats.poses_set += 1;
                tracing::info!("ros2: pose set");
            }
            Command::MotionPrior(m) => {
                if let Err(e) = self.prior.push(&m) {
                    tracing::warn!("{}: {e}; ignored", self.config.motion_prior_topic);
                } else {
                    self.pending_prior = true;
                }
            }
        }
    }

    fn refuse(&mut self, msg: &msgs::PointCloud2, what: &str) {
        self.stats.clouds_refused += 1;
        tracing::warn!(
            "{} cloud stamped {}.{:09} (frame `{}`): {what}; skipped",
            self.points_topic,
            msg.header.stamp.sec,
            msg.header.stamp.nanosec,
            msg.header.frame_id
        );
    }

    fn cloud(
        &mut self,
        odometry: &mut Odometry,
        msg: &msgs::PointCloud2,
        taken: Instant,
        on_frame: &mut impl FnMut(&Published),
    ) {
        if let Some(f) = &self.cloud_frame {
            if *f != msg.header.frame_id {
                let what = format!(
                    "frame_id changed from `{f}` (the node's first cloud; publish reset to start \
                     over in another frame)"
                );
                return self.refuse(msg, &what);
            }
        }
        let started = Instant::now();
        let cloud = match CloudFramer::cloud(&msg.view()) {
            Ok(c) => c,
            Err(e) => return self.refuse(msg, &e.to_string()),
        };
        let finite = cloud
            .points
            .iter()
            .filter(|p| p.iter().all(|v| v.is_finite()))
            .count();
        if finite == 0 {
            let what = format!("none of its {} points is finite", cloud.points.len());
            return self.refuse(msg, &what);
        }
        let decoded = started.elapsed().as_secs_f64();
        let frame = match self.framer.frame(&cloud, self.next_index) {
            Ok(f) => f,
            Err(e) => return self.refuse(msg, &e),
        };
        tracing::debug!(
            "ros2: cloud {}: waited {:.2} ms, decoded in {:.2} ms, framed in {:.2} ms",
            self.next_index,
            1e3 * (started - taken).as_secs_f64(),
            1e3 * decoded,
            1e3 * (started.elapsed().as_secs_f64() - decoded)
        );
        let header = (msg.header.stamp.to_ns(), msg.header.frame_id.as_str());
        if let Err(e) = self.register(odometry, &frame, header, taken, on_frame) {
            self.refuse(msg, &e);
        }
    }

    /// Registers a frame whose cloud was stamped `stamp_ns` in `frame_id`, publishes the
    /// results; `Err` is the stage's message.
    pub(crate) fn register(
        &mut self,
        odometry: &mut Odometry,
        frame: &LidarFrame,
        (stamp_ns, frame_id): (i64, &str),
        taken: Instant,
        on_frame: &mut impl FnMut(&Published),
    ) -> Result<(), String> {
        self.apply_prior(odometry, frame);
        let t = Instant::now();
        let processed = odometry.process_guarded(frame, self.want_features);
        let seconds = t.elapsed().as_secs_f64();
        let (result, features) = processed.map_err(|e| e.to_string())?;
        self.cloud_frame = Some(frame_id.to_string());
        self.next_index += 1;
        // The end of the scan on the cloud's own clock: its stamp plus the latest point time.
        let end_ns = stamp_ns + ((result.stamp - frame.timestamp) * 1e9).round() as i64;
        let published = Instant::now();
        self.publish(
            odometry,
            &result,
            frame,
            features.as_ref(),
            frame_id,
            end_ns,
        );
        tracing::debug!(
            "ros2: frame {}: stages {:.2} ms, publishing {:.2} ms",
            result.index,
            1e3 * seconds,
            1e3 * published.elapsed().as_secs_f64()
        );
        self.stats.frames += 1;
        on_frame(&Published {
            result: &result,
            stamp_ns: end_ns,
            seconds,
            in_node_seconds: taken.elapsed().as_secs_f64(),
        });
        Ok(())
    }

    /// Gives the registrar the other odometry's motion between the last scan and this one.
    fn apply_prior(&mut self, odometry: &mut Odometry, frame: &LidarFrame) {
        if !self.pending_prior {
            return;
        }
        let Some((_, t0)) = self.previous else {
            return;
        };
        let Some(base_motion) = self.prior.motion(t0, frame.end_stamp()) else {
            tracing::debug!("ros2: no motion prior covers this scan; the motion model is used");
            return;
        };
        // The other odometry tracks the base; keylo's motion is the LiDAR's.
        let a = self.base.extrinsic();
        let lidar_motion = a.inverse() * base_motion * a;
        match odometry.set_motion_prior(&lidar_motion) {
            Ok(()) => self.stats.motion_priors_used += 1,
            Err(e) => {
                tracing::warn!("ros2: motion prior refused: {e}");
                self.pending_prior = false;
            }
        }
    }

    fn publish(
        &mut self,
        odometry: &Odometry,
        r: &FrameResult,
        frame: &LidarFrame,
        features: Option<&FrameFeatures>,
        cloud_frame: &str,
        stamp_ns: i64,
    ) {
        let stamp = Time::from_ns(stamp_ns);
        let base_frame = if self.config.base_frame.is_empty() {
            cloud_frame
        } else {
            self.config.base_frame.as_str()
        };
        let (odom, estimated) = outputs::odometry(
            r,
            &OdometryParts {
                odom_frame: &self.config.lidar_odom_frame,
                base_frame,
                stamp,
                previous: self.previous,
                base: &self.base,
                anchor: &self.anchor,
                sigma: self.config.residual_sigma_m,
                fallback: (
                    self.config.position_covariance,
                    self.config.orientation_covariance,
                ),
            },
        );
        if !estimated {
            self.stats.fallback_covariances += 1;
        }
        let raw_base = self.base.base_pose(&r.pose);
        let base_pose = self.anchor * raw_base;
        self.last_raw_base = Some(raw_base);
        self.previous = Some((base_pose, r.stamp));
        let w = &self.dds.writers;
        let topic = &self.config.odometry_topic;
        if let Some(tf) = &w.tf {
            report(
                tf.publish(outputs::tf(&odom, &base_pose, self.config.invert_odom_tf)),
                "/tf",
            );
        }
        if let Some(p) = &w.path {
            report(p.publish(self.path.push(&odom)), &self.config.path_topic);
        }
        if let Some(p) = &w.registered_cloud {
            if let Some(c) = odometry.last_cloud() {
                let m = outputs::cloud(c.points.iter().copied(), stamp, cloud_frame);
                report(p.publish(m), &self.config.registered_cloud_topic);
            }
        }
        if let (Some(p), Some(f)) = (&w.keypoint_cloud, features) {
            let pts = outputs::keypoint_points(frame, f);
            let m = outputs::cloud(pts.into_iter(), stamp, cloud_frame);
            report(p.publish(m), &self.config.keypoint_cloud_topic);
        }
        if let Some(p) = &w.local_map {
            // The map is in the first scan's LiDAR frame; the odometry frame is the base's.
            let to_odom = self.anchor * self.base.extrinsic();
            let pts = odometry.local_map().into_iter().map(|q| to_odom * q);
            let m = outputs::cloud(pts, stamp, &self.config.lidar_odom_frame);
            report(p.publish(m), &self.config.local_map_topic);
        }
        if let (Some(p), Some(f)) = (&w.keypoint_image, features) {
            if let Some(m) = outputs::keypoint_image(f, stamp, cloud_frame) {
                report(p.publish(m), &self.config.keypoint_image_topic);
            }
        }
        report(w.odometry.publish(odom), topic);
    }
}

fn report<E: std::fmt::Debug>(r: Result<(), E>, topic: &str) {
    if let Err(e) = r {
        tracing::warn!("{topic}: publishing failed: {e:?}");
    }
}
