//! The node's loop: take the newest waiting cloud, make it a frame as `keylo run` does for a
//! bag's clouds, register it, publish odometry, TF, path and the debug topics. A bad cloud is
//! a log line naming the topic, stamp and what is wrong, and the loop goes on.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use keylo_core::{FrameFeatures, FrameResult, LidarFrame, Odometry};
use keylo_io::cloud::{ProjectionConfig, Projector, Sensor};
use keylo_io::ros::CloudFramer;
use keylo_map::covariance::{array, frame_covariance, matrix, NoiseModel, PLAIN_SIGMA_M};
use nalgebra::Isometry3;

use crate::dds::Dds;
use crate::frames::{self, BaseFrame};
use crate::msgs;
use crate::outputs::PathKeeper;
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
    /// Frames registered (published, or, for a localiser not tracking, logged and counted in
    /// `frames_not_tracking`).
    pub frames: u64,
    /// Localisation in a prior map (`[registrar] kind = "localise"`): registered frames that
    /// were not tracking, so nothing was published for them (no odometry, TF or path: a pose
    /// not to be trusted is not reported as one).
    pub frames_not_tracking: u64,
    /// Frames whose covariance was the fixed fallback (no estimate from the registrar).
    pub fallback_covariances: u64,
    /// Frames whose initial guess came from the motion prior topic.
    pub motion_priors_used: u64,
    /// Reset and set-pose commands carried out.
    pub resets: u64,
    pub poses_set: u64,
}

/// One registered frame, as the node published it (a localiser's frame that was not tracking
/// comes here too, with nothing published).
pub struct Published<'a> {
    pub result: &'a FrameResult,
    /// The pipeline after the frame (its registered cloud, its local map).
    pub odometry: &'a Odometry,
    /// The frame registered (sensor frame, as the cloud made it).
    pub frame: &'a LidarFrame,
    /// What the feature stages made of it, when the node asked for them
    /// ([`Ros2Node::want_features`]).
    pub features: Option<&'a FrameFeatures>,
    /// Resets so far (`keylo/reset`): a new count starts a new trajectory at the identity.
    pub resets: u64,
    /// The odometry message's stamp (the scan's end, on the cloud's clock), nanoseconds.
    pub stamp_ns: i64,
    /// Time spent in keylo's stages on this frame, seconds.
    pub seconds: f64,
    /// From the cloud taken from DDS (or the frame from the source) to its odometry published,
    /// seconds: waiting, decoding, the stages and publishing.
    pub in_node_seconds: f64,
    /// Of `in_node_seconds`: waiting in the node's queue until the loop took it.
    pub waited_seconds: f64,
    /// Of `in_node_seconds`: decoding the PointCloud2 and making the frame (0 for a source's
    /// frames, which come made).
    pub prepare_seconds: f64,
    /// Of `in_node_seconds`: making and writing the output messages.
    pub publish_seconds: f64,
}

/// When the node got a cloud and when its loop started on it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Held {
    /// Taken from DDS (or from the source's queue by its reading thread).
    pub taken: Instant,
    /// Taken from the node's queue by the registering loop.
    pub started: Instant,
}

/// The ROS 2 node: DDS in and out around an [`Odometry`].
pub struct Ros2Node {
    pub(crate) config: Ros2Config,
    pub(crate) dds: Dds,
    pub(crate) framer: CloudFramer,
    pub(crate) base: BaseFrame,
    pub(crate) points_topic: String,
    pub(crate) path: PathKeeper,
    pub(crate) prior: PriorTrack,
    /// The frame of the first cloud; later clouds must keep it.
    pub(crate) cloud_frame: Option<String>,
    /// The previous frame's published base pose and end stamp (s).
    pub(crate) previous: Option<(Isometry3<f64>, f64)>,
    /// The end stamp (s) of the last frame the registrar registered, published or not (a
    /// localiser's frame that was not tracking): where the next motion prior starts.
    pub(crate) last_registered: Option<f64>,
    /// The last frame's base pose before `anchor` (keylo's own, from the first scan).
    pub(crate) last_raw_base: Option<Isometry3<f64>>,
    /// Set by set-pose: published pose = anchor · keylo's base pose.
    pub(crate) anchor: Isometry3<f64>,
    pub(crate) next_index: u64,
    pub(crate) stats: NodeStats,
    pub(crate) want_features: bool,
    pub(crate) pending_prior: bool,
    /// The last frame's LiDAR pose (keylo's own), for the covariance's motion terms.
    pub(crate) last_lidar: Option<Isometry3<f64>>,
    /// How a frame's `H⁻¹` becomes its covariance.
    pub(crate) noise: NoiseModel,
    /// The registrar localises in a prior map (`localise`): set-pose relocalises it.
    pub(crate) localising: bool,
}

impl Ros2Node {
    /// Sets the covariance's noise model for the pipeline's registrar `kind`: with
    /// `ros2.residual_sigma_m = 0` the model fitted for it (plain `σ² H⁻¹` with σ = 0.03 m and
    /// a warning for a registrar without one), else plain `σ² H⁻¹` with the configured σ.
    /// A `localise` registrar makes no `H` (its frames take the fixed covariance) and makes
    /// set-pose a relocalisation.
    pub fn set_registrar(&mut self, kind: &str) {
        self.localising = kind == "localise";
        if self.localising {
            return;
        }
        let sigma = self.config.residual_sigma_m;
        self.noise = NoiseModel::for_registrar(kind, sigma, "ros2.residual_sigma_m");
    }

    /// The frame's covariance in the world frame, when the registrar estimated `H`.
    pub(crate) fn frame_covariance(&self, r: &FrameResult) -> Option<[[f64; 6]; 6]> {
        let h = r.degeneracy.as_ref()?.covariance(1.0)?;
        let c = frame_covariance(&self.noise, &matrix(&h), &r.pose, self.last_lidar.as_ref());
        Some(array(&c))
    }

    /// Asks for every frame's features in [`Published`] (e.g. to save them with a map), on
    /// top of what the debug topics need.
    pub fn want_features(&mut self, want: bool) {
        self.want_features |= want;
    }

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
        let points_topic = config.topic(&config.points_topic);
        tracing::info!(
            "ros2: listening on {points_topic} ({:?}), odometry on {}",
            config.input_reliability,
            config.topic(&config.odometry_topic)
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
            last_registered: None,
            last_raw_base: None,
            anchor: Isometry3::identity(),
            next_index: 0,
            stats: NodeStats::default(),
            pending_prior: false,
            last_lidar: None,
            noise: NoiseModel::plain(PLAIN_SIGMA_M),
            localising: false,
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
        let frame = match self.framer.frame_message(&msg.view(), self.next_index) {
            Ok(f) => f,
            Err(e) => return self.refuse(msg, &e),
        };
        if let Some(what) = no_points(&frame, msg) {
            return self.refuse(msg, &what);
        }
        tracing::debug!(
            "ros2: cloud {}: waited {:.2} ms, decoded and framed in {:.2} ms",
            self.next_index,
            1e3 * (started - taken).as_secs_f64(),
            1e3 * started.elapsed().as_secs_f64()
        );
        let header = (msg.header.stamp.to_ns(), msg.header.frame_id.as_str());
        let held = Held { taken, started };
        if let Err(e) = self.register(odometry, &frame, header, held, on_frame) {
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
        held: Held,
        on_frame: &mut impl FnMut(&Published),
    ) -> Result<(), String> {
        let prepare_seconds = held.started.elapsed().as_secs_f64();
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
        let publish_seconds = published.elapsed().as_secs_f64();
        tracing::debug!(
            "ros2: frame {}: stages {:.2} ms, publishing {:.2} ms",
            result.index,
            1e3 * seconds,
            1e3 * publish_seconds
        );
        self.stats.frames += 1;
        on_frame(&Published {
            result: &result,
            odometry,
            frame,
            features: features.as_ref(),
            resets: self.stats.resets,
            stamp_ns: end_ns,
            seconds,
            in_node_seconds: held.taken.elapsed().as_secs_f64(),
            waited_seconds: (held.started - held.taken).as_secs_f64(),
            prepare_seconds,
            publish_seconds,
        });
        Ok(())
    }
}

/// Why `frame` (of `msg`) holds nothing to register, if it does not: no finite point (an
/// unorganised cloud), no return (an organised one: every point non-finite or at the origin).
fn no_points(frame: &LidarFrame, msg: &msgs::PointCloud2) -> Option<String> {
    let n = u64::from(msg.width) * u64::from(msg.height);
    match &frame.scan {
        Some(scan) => scan
            .is_empty()
            .then(|| format!("none of its {n} points is finite")),
        None => (!frame.valid.contains(&true)).then(|| {
            format!("none of its {n} points is finite and away from the origin (a return)")
        }),
    }
}
