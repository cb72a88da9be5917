//! What every registrar does around its own alignment: refuse clouds with non-finite
//! values, run the work in the registrar's own thread pool when it has one, and stamp the
//! result with the time of the cloud's last point.

use keylo_core::{CoreError, PointCloud};

use crate::RegistrationError;

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
