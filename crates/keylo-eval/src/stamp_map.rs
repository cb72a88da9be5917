//! A reference's clock mapped onto the estimate's: `t · scale + offset`, for a reference
//! that counts time in other units (frames, milliseconds, nanoseconds) or from another origin
//! (Unix epoch against time since the start).

use keylo_core::Trajectory;

use crate::EvalError;

/// `t ↦ t · scale + offset_s`, applied to a reference's stamps before association.
///
/// ```
/// use keylo_core::{Pose, Trajectory};
/// use keylo_eval::stamp_map::StampMap;
/// let mut gt = Trajectory::default();
/// for i in 0..3 { gt.push(i as f64, Pose::identity()); } // frame indices
/// StampMap::new(0.1, 5.0)?.apply(&mut gt);
/// assert_eq!(gt.stamps, vec![5.0, 5.1, 5.2]);
/// # Ok::<(), keylo_eval::EvalError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StampMap {
    /// Factor on every stamp (finite, > 0; 1: seconds already).
    pub scale: f64,
    /// Seconds added after scaling (finite).
    pub offset_s: f64,
}

impl Default for StampMap {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl StampMap {
    /// Stamps left as they are.
    pub const IDENTITY: Self = Self {
        scale: 1.0,
        offset_s: 0.0,
    };

    /// A checked map: `scale` finite and > 0, `offset_s` finite.
    pub fn new(scale: f64, offset_s: f64) -> Result<Self, EvalError> {
        if !(scale.is_finite() && scale > 0.0) {
            return Err(EvalError::InvalidOption {
                name: "time scale",
                reason: format!("{scale} is not a finite number > 0"),
            });
        }
        if !offset_s.is_finite() {
            return Err(EvalError::InvalidOption {
                name: "time offset",
                reason: format!("{offset_s} is not a finite number of seconds"),
            });
        }
        Ok(Self { scale, offset_s })
    }

    /// True when stamps are left as they are.
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// One stamp mapped.
    pub fn map(&self, t: f64) -> f64 {
        t * self.scale + self.offset_s
    }

    /// `self`, then `next`: one map with the effect of both.
    ///
    /// ```
    /// use keylo_eval::stamp_map::StampMap;
    /// let both = StampMap::new(0.5, 1.0)?.then(&StampMap::new(0.1, 2.0)?);
    /// assert!((both.map(10.0) - 2.6).abs() < 1e-12);
    /// # Ok::<(), keylo_eval::EvalError>(())
    /// ```
    pub fn then(&self, next: &Self) -> Self {
        Self {
            scale: self.scale * next.scale,
            offset_s: self.offset_s * next.scale + next.offset_s,
        }
    }

    /// Maps every stamp of `traj` in place.
    pub fn apply(&self, traj: &mut Trajectory) {
        if self.is_identity() {
            return;
        }
        for t in &mut traj.stamps {
            *t = self.map(*t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_name_the_option() {
        for (s, o, name) in [
            (0.0, 0.0, "time scale"),
            (-1.0, 0.0, "time scale"),
            (f64::NAN, 0.0, "time scale"),
            (f64::INFINITY, 0.0, "time scale"),
            (1.0, f64::NAN, "time offset"),
        ] {
            let msg = StampMap::new(s, o).unwrap_err().to_string();
            assert!(msg.contains(name), "{msg}");
        }
        assert!(StampMap::new(1e-9, -1.6e9).is_ok());
    }

    #[test]
    fn identity_leaves_stamps_alone() {
        assert!(StampMap::default().is_identity());
        assert_eq!(StampMap::new(1e-3, 2.0).unwrap().map(1500.0), 3.5);
    }
}
