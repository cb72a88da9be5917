use crate::{CoreError, Degeneracy, FrameKeypoints, PointCloud, Pose};

/// The outcome of registering one cloud.
#[derive(Debug, Clone, PartialEq)]
pub struct Registration {
    /// Time the pose refers to, seconds: the instant the registrar deskews the scan to
    /// (KISS-ICP: the end of the scan; the scan start when the cloud has no per-point times).
    /// [`crate::Odometry`] does not use it: its results are stamped at the frame's end
    /// ([`crate::LidarFrame::end_stamp`]), which does not depend on the points a downsampler
    /// kept and which a registrar, seeing only the cloud, cannot know.
    pub stamp: f64,
    /// Pose of the sensor at `stamp` in the world (first-frame) frame.
    pub pose: Pose,
    /// Points used for registration after the registrar's own preprocessing.
    pub source_points: usize,
    /// Iterations the solver ran.
    pub iterations: usize,
    /// Whether the solver met its convergence rule (false: stopped at the iteration cap).
    pub converged: bool,
    /// How well the geometry constrained the pose (eigen-analysis of the normal equations at
    /// convergence), for registrars that report it.
    pub degeneracy: Option<Degeneracy>,
    /// How well the cloud fits a fixed prior map, for registrars that localise in one
    /// (`localise`); `None` for odometry.
    pub fit: Option<MapFit>,
}

/// How well a registered cloud fits a fixed prior map (localisation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapFit {
    /// Share of the registered points with a map point within the registrar's fitness
    /// distance.
    pub fitness: f64,
    /// `fitness` reached the registrar's threshold: the pose is tracked. A frame that is not
    /// tracking has a pose that is not to be trusted.
    pub tracking: bool,
}

/// Estimates the sensor pose of each cloud against its own local map (odometry).
///
/// Owns: the local map, the motion model and everything needed between frames. Clouds arrive in
/// time order; an error leaves the state as it was before the call.
pub trait Registrar: Send {
    /// Registers the next cloud and returns its pose.
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError>;

    /// Whether [`Self::register_with_keypoints`] uses the keypoints: the pipeline then maps
    /// every described keypoint to its 3-D point and calls it instead of [`Self::register`].
    /// By default false.
    fn wants_keypoints(&self) -> bool {
        false
    }

    /// Registers the next cloud, given also the frame's described keypoints with their
    /// points (sensor frame, times relative to the frame's timestamp, as the cloud's).
    /// Registrars that match keypoints between frames (`hybrid`) override it; by default
    /// the keypoints are ignored.
    fn register_with_keypoints(
        &mut self,
        cloud: &PointCloud,
        keypoints: &FrameKeypoints,
    ) -> Result<Registration, CoreError> {
        let _ = keypoints;
        self.register(cloud)
    }

    /// Points currently in the local map.
    fn map_size(&self) -> usize;

    /// Whether the registrar takes a cloud without a point (an empty scan) and gives it a
    /// pose of its own (KISS-ICP's constant-velocity prediction). By default false: the
    /// pipeline stops such a frame with an error before calling the registrar.
    fn accepts_empty_clouds(&self) -> bool {
        false
    }

    /// The registered points ([`Registration::source_points`]) below which this registrar
    /// cannot constrain six degrees of freedom: such a frame is reported degenerate
    /// ([`crate::Degenerate`]). By default [`crate::degenerate::DEFAULT_MIN_POINTS`] (six).
    fn min_points(&self) -> usize {
        crate::degenerate::DEFAULT_MIN_POINTS
    }

    /// SLAM hook: the motion from the last registered frame to the next one (sensor frame
    /// of the last, as `last_pose⁻¹ · next_pose`), e.g. from an IMU or wheel odometry. The
    /// next call to `register` uses it instead of its own motion model (constant velocity)
    /// for the initial guess and for deskewing, then forgets it (successful or not). By
    /// default unsupported: an error naming the hook.
    fn set_motion_prior(&mut self, delta: &Pose) -> Result<(), CoreError> {
        let _ = delta;
        Err(unsupported("set_motion_prior"))
    }

    /// SLAM hook: forget the map and the motion, as a new registrar (relocalisation from
    /// scratch). By default unsupported.
    fn reset(&mut self) -> Result<(), CoreError> {
        Err(unsupported("reset"))
    }

    /// SLAM hook: the pose of the last registered frame becomes `pose` (a correction from a
    /// back end or a relocalisation); the map and the motion model are kept. By default
    /// unsupported.
    fn set_pose(&mut self, pose: &Pose) -> Result<(), CoreError> {
        let _ = pose;
        Err(unsupported("set_pose"))
    }

    /// SLAM hook: the points of the local map, world frame. Empty by default.
    fn local_map(&self) -> Vec<nalgebra::Point3<f64>> {
        Vec::new()
    }
}

fn unsupported(hook: &str) -> CoreError {
    CoreError::stage(
        "registrar",
        format!("this registrar does not offer `{hook}`"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A registrar that implements only what it must.
    struct Minimal;

    impl Registrar for Minimal {
        fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
            Ok(Registration {
                stamp: cloud.timestamp,
                pose: Pose::identity(),
                source_points: cloud.len(),
                iterations: 0,
                converged: true,
                degeneracy: None,
                fit: None,
            })
        }
        fn map_size(&self) -> usize {
            0
        }
    }

    #[test]
    fn hooks_a_registrar_does_not_offer_are_errors_naming_them() {
        let mut r = Minimal;
        let id = Pose::identity();
        let outcomes = [
            ("set_motion_prior", r.set_motion_prior(&id)),
            ("reset", r.reset()),
            ("set_pose", r.set_pose(&id)),
        ];
        for (hook, e) in outcomes {
            let text = e.unwrap_err().to_string();
            assert!(
                text.contains(hook) && text.contains("does not offer"),
                "{text}"
            );
        }
        assert!(r.local_map().is_empty());
        assert!(!r.accepts_empty_clouds());
    }
}
