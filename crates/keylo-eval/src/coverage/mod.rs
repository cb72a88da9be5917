//! Association coverage: how many estimated poses found a reference pose, the two time ranges,
//! and, when fewer than [`MIN_FRACTION`] did, the likely cause ([`LikelyCause`]). Figures over
//! a few associated poses mislead; this says so and why.

mod cause;
mod clock;

use keylo_core::Trajectory;
use serde::Serialize;

use crate::associate::Associated;
pub use cause::LikelyCause;
pub use clock::TimeRange;

/// Share of the estimated poses that must associate before the figures are trusted.
pub const MIN_FRACTION: f64 = 0.9;

/// How well an estimate's stamps met the reference's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Coverage {
    /// Estimated poses paired with a reference pose.
    pub associated: usize,
    /// Estimated poses.
    pub estimated: usize,
    /// Share associated (0 without estimated poses).
    pub fraction: f64,
    /// The estimate's first and last stamp, seconds (`None`: no finite stamp).
    pub estimate_range_s: Option<TimeRange>,
    /// The reference's first and last stamp, after any [`crate::stamp_map::StampMap`].
    pub reference_range_s: Option<TimeRange>,
    /// Why so few associate, when fewer than [`MIN_FRACTION`] did.
    pub likely_cause: Option<LikelyCause>,
}

/// The coverage of `associated` of the `estimate` stamps, matched against `reference`
/// within `max_diff` seconds (the association's bound, used to tell a shift from noise).
///
/// ```
/// use keylo_eval::coverage::{coverage, LikelyCause};
/// let est: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
/// let frames: Vec<f64> = (0..100).map(|i| i as f64).collect();
/// let c = coverage(&est, &frames, 10, 0.01);
/// assert!(c.is_low());
/// let Some(LikelyCause::FrameIndices { scale, .. }) = c.likely_cause else { panic!() };
/// assert_eq!(scale, 0.1);
/// ```
pub fn coverage(estimate: &[f64], reference: &[f64], associated: usize, max_diff: f64) -> Coverage {
    let estimated = estimate.len();
    let fraction = if estimated == 0 {
        0.0
    } else {
        associated.min(estimated) as f64 / estimated as f64
    };
    let low = estimated > 0 && fraction < MIN_FRACTION;
    Coverage {
        associated,
        estimated,
        fraction,
        estimate_range_s: TimeRange::of(estimate),
        reference_range_s: TimeRange::of(reference),
        likely_cause: low.then(|| cause::diagnose(estimate, reference, max_diff)),
    }
}

/// [`coverage`] of `estimate` against `reference` given their pairs (`None`: none matched);
/// an estimated pose paired twice counts once.
pub fn coverage_of(
    estimate: &Trajectory,
    reference: &Trajectory,
    pairs: Option<&Associated>,
    max_diff: f64,
) -> Coverage {
    let associated = pairs.map_or(0, |p| {
        let mut ids = p.estimate_indices.clone();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    });
    coverage(&estimate.stamps, &reference.stamps, associated, max_diff)
}

/// [`coverage_of`] with the pairs [`crate::associate::associate`] makes under `opts`.
pub fn of_pairing(
    estimate: &Trajectory,
    reference: &Trajectory,
    opts: &crate::associate::AssociateOptions,
) -> Coverage {
    let pairs = crate::associate::associate(reference, estimate, opts).ok();
    coverage_of(estimate, reference, pairs.as_ref(), opts.max_diff)
}

/// [`coverage_of`] with the pairs [`crate::evaluate`] makes under `opts`.
pub fn of_evaluation(
    estimate: &Trajectory,
    reference: &Trajectory,
    opts: &crate::EvalOptions,
) -> Coverage {
    of_pairing(estimate, reference, &opts.associate)
}

/// `keylo eval --json`'s document (also `keylo.evaluate`'s dict): the figures, the
/// reference's name and the association.
#[derive(Debug, Serialize)]
pub struct EvalDocument<'a> {
    /// The figures, at the document's top level.
    #[serde(flatten)]
    pub accuracy: &'a crate::Accuracy,
    /// The reference's name (`--gt-label`, else its file name).
    pub reference_label: &'a str,
    /// How many estimated poses paired with the reference, and why not more.
    pub association: &'a Coverage,
}

/// A time range for messages, `none` when there is none.
pub fn range_text(r: Option<TimeRange>) -> String {
    r.map_or("none".into(), |r| r.to_string())
}

impl Coverage {
    /// Fewer than [`MIN_FRACTION`] of the estimated poses associated.
    pub fn is_low(&self) -> bool {
        self.likely_cause.is_some()
    }

    /// `16/154`.
    pub fn ratio(&self) -> String {
        format!("{}/{}", self.associated, self.estimated)
    }

    /// The figures in words, naming the reference by `reference`: "only 16 of 154 estimated
    /// poses (10 %) associate with gt.tum (estimate times 0.000 … 15.300 s, gt.tum times
    /// 0.000 … 153.000 s)".
    pub fn describe(&self, reference: &str) -> String {
        format!(
            "{}{} of {} estimated poses ({:.0} %) associate with {reference} (estimate times \
             {} s, {reference} times {} s)",
            if self.is_low() { "only " } else { "" },
            self.associated,
            self.estimated,
            // Floored: 89.6 % must not read "90 %" under a 90 % threshold.
            (100.0 * self.fraction).floor(),
            range_text(self.estimate_range_s),
            range_text(self.reference_range_s),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::associate::{associate, AssociateOptions};
    use keylo_core::Pose;

    fn traj(stamps: impl Iterator<Item = f64>) -> Trajectory {
        let mut t = Trajectory::default();
        for s in stamps {
            t.push(s, Pose::translation(s, 0.0, 0.0));
        }
        t
    }

    #[test]
    fn ninety_percent_or_more_gives_no_warning() {
        let est: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
        let c = coverage(&est, &est[..90], 90, 0.01);
        assert!(!c.is_low(), "{c:?}");
        assert_eq!(c.ratio(), "90/100");
        assert!(coverage(&est, &est[..89], 89, 0.01).is_low());
    }

    #[test]
    fn counts_come_from_the_pairs() {
        let est = traj((0..154).map(|i| i as f64 * 0.1));
        let frames = traj((0..154).map(f64::from));
        let pairs = associate(&frames, &est, &AssociateOptions::default()).unwrap();
        let c = coverage_of(&est, &frames, Some(&pairs), 0.01);
        assert_eq!(c.ratio(), "16/154");
        let text = c.describe("gt.tum");
        assert!(
            text.starts_with("only 16 of 154 estimated poses (10 %)"),
            "{text}"
        );
        assert!(text.contains("gt.tum times 0.000 … 153.000 s"), "{text}");
        assert_eq!(coverage_of(&est, &frames, None, 0.01).associated, 0);
    }

    #[test]
    fn no_estimate_is_not_low() {
        let c = coverage(&[], &[1.0], 0, 0.01);
        assert!(!c.is_low() && c.estimate_range_s.is_none());
    }
}
