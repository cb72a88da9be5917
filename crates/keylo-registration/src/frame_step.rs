//! What every registrar does around its own alignment: refuse clouds with non-finite
//! values and external priors or poses that are not rigid, run the work in the registrar's
//! own thread pool when it has one, deskew and range-filter the scan, and stamp the result
//! with the time of the cloud's last point.

pub(crate) use keylo_core::rigid::check_rigid;
use keylo_core::{CoreError, PointCloud};
use nalgebra::{Isometry3, Point3};

use crate::kiss_icp::deskew;
use crate::RegistrationError;

/// The registrar's own pool of `max_num_threads` workers; `None` for 0 (the caller's pool).
pub(crate) fn own_pool(
    max_num_threads: usize,
) -> Result<Option<rayon::ThreadPool>, RegistrationError> {
    if max_num_threads == 0 {
        return Ok(None);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(max_num_threads)
        .build()
        .map(Some)
        .map_err(|e| RegistrationError::BadParameter {
            field: "max_num_threads",
            value: max_num_threads.to_string(),
            expected: format!("a thread count the system allows ({e})"),
        })
}

/// The cloud's points, deskewed with `last_delta` when `deskew` is set and the cloud has
/// per-point times, keeping those with `min < range < max` (upstream kiss-icp's
/// `Preprocessor`).
pub(crate) fn deskew_and_crop(
    cloud: &PointCloud,
    deskew: bool,
    last_delta: &Isometry3<f64>,
    range: (f64, f64),
) -> Vec<Point3<f64>> {
    let mut points = Vec::new();
    deskew_and_crop_into(cloud, deskew, last_delta, range, &mut points);
    points
}

/// [`deskew_and_crop`] into `out` (cleared first), whose buffer is reused.
pub(crate) fn deskew_and_crop_into(
    cloud: &PointCloud,
    deskew: bool,
    last_delta: &Isometry3<f64>,
    (min, max): (f64, f64),
    out: &mut Vec<Point3<f64>>,
) {
    out.clear();
    let in_range = |p: &Point3<f64>| {
        let r = p.coords.norm();
        r > min && r < max
    };
    match (deskew, &cloud.times) {
        (true, Some(times)) => {
            out.extend_from_slice(&cloud.points);
            deskew::deskew(out, times, last_delta);
            out.retain(in_range);
        }
        _ => out.extend(cloud.points.iter().filter(|p| in_range(p))),
    }
}

/// The error for a cloud with no point between `min` and `max` range: it gives the nearest
/// and farthest point, and asks about units when they are all beyond `max` (a cloud in
/// millimetres, say).
pub(crate) fn nothing_in_range(cloud: &PointCloud, (min, max): (f64, f64)) -> RegistrationError {
    let ranges = cloud.points.iter().map(|p| p.coords.norm());
    let (near, far) = ranges.fold((f64::INFINITY, 0.0f64), |(n, f), r| (n.min(r), f.max(r)));
    let mut message = format!(
        "no point within min_range {min} m and max_range {max} m (of {} input points",
        cloud.len()
    );
    if cloud.is_empty() {
        message.push(')');
    } else {
        message.push_str(&format!("; they lie {near:.3e} to {far:.3e} m away)"));
    }
    if near >= max && near.is_finite() {
        message.push_str(
            ": all are beyond max_range; are the coordinates in metres? (a cloud in \
             millimetres is 1000× too far), or is max_range too small?",
        );
    }
    RegistrationError::BadCloud(message)
}

/// An error naming the first point with a non-finite coordinate or time.
pub(crate) fn reject_non_finite(cloud: &PointCloud) -> Result<(), CoreError> {
    match cloud.first_non_finite() {
        Some(i) => Err(RegistrationError::BadCloud(format!(
            "point {i} has a non-finite coordinate or time"
        ))
        .into()),
        None => Ok(()),
    }
}

/// `work(this)` inside the pool that `pool(this)` holds (taken out for the call and put
/// back), or on the caller's pool when there is none.
pub(crate) fn in_own_pool<S, T>(
    this: &mut S,
    pool: fn(&mut S) -> &mut Option<rayon::ThreadPool>,
    work: impl FnOnce(&mut S) -> T + Send,
) -> T
where
    S: Send,
    T: Send,
{
    match pool(this).take() {
        Some(p) => {
            let out = p.install(|| work(this));
            *pool(this) = Some(p);
            out
        }
        None => work(this),
    }
}

/// The stamp of a registration: the cloud's stamp plus its latest point time.
pub(crate) fn end_stamp(cloud: &PointCloud) -> f64 {
    let end = cloud
        .times
        .as_ref()
        .and_then(|t| t.iter().copied().reduce(f64::max))
        .unwrap_or(0.0);
    cloud.timestamp + end
}

/// Refuses a motion prior that is not rigid or steps beyond `bound` (m; 0: no bound).
pub(crate) fn check_prior(delta: &Isometry3<f64>, bound: f64) -> Result<(), CoreError> {
    check_rigid(delta, "motion prior")?;
    let step = delta.translation.vector.norm();
    if bound > 0.0 && step > bound {
        return Err(CoreError::stage(
            "registrar",
            format!(
                "motion prior: a step of {step:.3} m is beyond `max_motion_per_frame` = {bound} m"
            ),
        ));
    }
    Ok(())
}

/// The divergence guard of a registrar named `who`: an error when `pose` moved a non-finite
/// distance, or more than `bound` (m; 0: no bound) from `last`.
pub(crate) fn check_motion(
    who: &str,
    last: &Isometry3<f64>,
    pose: &Isometry3<f64>,
    bound: f64,
) -> Result<(), RegistrationError> {
    let step = (last.inverse() * pose).translation.vector.norm();
    if !step.is_finite() || (bound > 0.0 && step > bound) {
        return Err(RegistrationError::Diverged(format!(
            "{who} diverged: the pose moved {step:.3} m in one frame (bound \
             `max_motion_per_frame` = {bound} m)"
        )));
    }
    Ok(())
}
