//! Why few estimated stamps meet a reference stamp: the usual clock mistakes (frame indices,
//! a power of ten, another origin, a constant shift), each with the [`StampMap`] that
//! undoes it where one does.

use serde::Serialize;

use super::clock::{
    median, median_step, round_offset, round_significant, seconds, simplest, TimeRange,
};
use crate::stamp_map::StampMap;

/// Reference span / estimate span factors taken as a unit mistake, with the scale that undoes
/// each: tenths and hundredths of a second, ms, µs, ns.
const POWERS_OF_TEN: [(f64, f64); 5] = [
    (10.0, 0.1),
    (100.0, 0.01),
    (1e3, 1e-3),
    (1e6, 1e-6),
    (1e9, 1e-9),
];
/// How far (relative) a span ratio may be from a power of ten.
const RATIO_TOLERANCE: f64 = 0.15;
/// Share of the estimate's span the reference must cover not to be called short.
const MIN_COVER: f64 = 0.9;

/// The likely reason few estimated poses associate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum LikelyCause {
    /// The reference's times are frame indices (whole numbers, step 1) while the estimate's
    /// are seconds `scale` apart.
    FrameIndices {
        /// The estimate's step, the scale that undoes it.
        scale: f64,
        /// Seconds to add after scaling so the first stamps meet.
        offset_s: f64,
    },
    /// The reference spans `factor` (a power of ten) times the estimate's time: other units.
    PowerOfTen {
        /// Reference span / estimate span, rounded (10, 100, 1e3, 1e6, 1e9).
        factor: f64,
        /// `1 / factor`.
        scale: f64,
        /// Seconds to add after scaling so the first stamps meet.
        offset_s: f64,
    },
    /// The two time ranges are apart, or overlap only partly though equally long: other
    /// origins (e.g. Unix epoch against time since the start).
    Offset {
        /// Estimate's first stamp − reference's first stamp.
        offset_s: f64,
    },
    /// The ranges overlap but every reference stamp sits a constant time from its estimate.
    Shift {
        /// Seconds to add to the reference's stamps.
        offset_s: f64,
    },
    /// The reference covers only part of the estimate's time.
    ShortReference {
        /// Share of the estimate's span it covers.
        covered: f64,
    },
    /// Reference poses are too far apart for most estimated stamps to fall near one.
    SparseReference {
        /// Median reference step, seconds.
        step_s: f64,
        /// The association's largest stamp difference, seconds.
        max_diff_s: f64,
    },
    /// None of the above.
    Unknown,
}

impl LikelyCause {
    /// The reference time map that undoes the cause, when one does.
    pub fn fix(&self) -> Option<StampMap> {
        let (scale, offset_s) = match *self {
            Self::FrameIndices { scale, offset_s }
            | Self::PowerOfTen {
                scale, offset_s, ..
            } => (scale, offset_s),
            Self::Offset { offset_s } | Self::Shift { offset_s } => (1.0, offset_s),
            _ => return None,
        };
        Some(StampMap { scale, offset_s })
    }
}

impl std::fmt::Display for LikelyCause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::FrameIndices { scale, .. } => write!(
                f,
                "the reference's times look like frame indices (whole numbers 1 apart) while \
                 the estimate's are seconds {scale} s apart"
            ),
            Self::PowerOfTen { factor, .. } => write!(
                f,
                "the reference's time span is {factor:e} times the estimate's: its times are \
                 likely in {}",
                unit_of(factor)
            ),
            Self::Offset { offset_s } => write!(
                f,
                "the two clocks start at other times (e.g. Unix epoch against time since the \
                 start): the estimate starts {} s {} the reference",
                seconds(offset_s.abs()),
                if offset_s < 0.0 { "before" } else { "after" }
            ),
            Self::Shift { offset_s } => write!(
                f,
                "the reference's stamps sit a constant {} s from the estimate's",
                seconds(-offset_s)
            ),
            Self::ShortReference { covered } => write!(
                f,
                "the reference covers only {:.0} % of the estimate's time",
                100.0 * covered
            ),
            Self::SparseReference { step_s, max_diff_s } => write!(
                f,
                "the reference's poses are {step_s} s apart, too far for most estimated \
                 stamps to fall within {max_diff_s} s of one"
            ),
            Self::Unknown => write!(f, "no common clock mistake fits"),
        }
    }
}

fn unit_of(factor: f64) -> &'static str {
    match factor {
        1e3 => "milliseconds",
        1e6 => "microseconds",
        1e9 => "nanoseconds",
        _ => "another unit (or counts frames)",
    }
}

/// The likely cause, trying the common mistakes in turn. A mistake with a fix is named only
/// when its fix, applied to the reference, pairs at least [`super::MIN_FRACTION`] of the
/// estimated stamps (a 1 Hz reference on whole seconds looks like frame indices, but scaling
/// it by 0.1 would not help: it is sparse).
pub fn diagnose(estimate: &[f64], reference: &[f64], max_diff: f64) -> LikelyCause {
    let (Some(e), Some(r)) = (TimeRange::of(estimate), TimeRange::of(reference)) else {
        return LikelyCause::Unknown;
    };
    let meet = |scale: f64| round_offset(e.first - r.first * scale, max_diff);
    let frames = frame_index_scale(estimate, reference).map(|scale| LikelyCause::FrameIndices {
        scale,
        offset_s: meet(scale),
    });
    let units = power_of_ten(e.span(), r.span()).map(|(factor, scale)| LikelyCause::PowerOfTen {
        factor,
        scale,
        offset_s: meet(scale),
    });
    let apart = e.last < r.first - max_diff || r.last < e.first - max_diff;
    let short = e.span() > 0.0 && e.overlap(&r) < MIN_COVER * e.span();
    let same_length = (r.span() / e.span() - 1.0).abs() <= RATIO_TOLERANCE;
    let offset = (apart || (short && same_length)).then(|| LikelyCause::Offset {
        offset_s: meet(1.0),
    });
    let shift = constant_shift(estimate, reference, max_diff)
        .map(|offset_s| LikelyCause::Shift { offset_s });
    let fixes = |c: &LikelyCause| {
        c.fix().is_some_and(|m| {
            paired_fraction(estimate, reference, m, max_diff) >= super::MIN_FRACTION
        })
    };
    if let Some(c) = [frames, units, offset].into_iter().flatten().find(fixes) {
        return c;
    }
    if short {
        return LikelyCause::ShortReference {
            covered: e.overlap(&r) / e.span(),
        };
    }
    if let Some(c) = shift.filter(fixes) {
        return c;
    }
    match median_step(reference) {
        Some(step_s) if step_s > 2.0 * max_diff => LikelyCause::SparseReference {
            step_s: round_significant(step_s, 6),
            max_diff_s: max_diff,
        },
        _ => LikelyCause::Unknown,
    }
}

/// The share of `estimate`'s stamps within `max_diff` of a reference stamp once `map` is
/// applied to the reference.
fn paired_fraction(estimate: &[f64], reference: &[f64], map: StampMap, max_diff: f64) -> f64 {
    let mut mapped: Vec<f64> = reference
        .iter()
        .map(|&t| map.map(t))
        .filter(|t| t.is_finite())
        .collect();
    mapped.sort_by(f64::total_cmp);
    let near = |t: f64| nearest(&mapped, t).is_some_and(|d| d.abs() <= max_diff);
    let paired = estimate.iter().filter(|&&t| near(t)).count();
    paired as f64 / estimate.len().max(1) as f64
}

/// The signed time from `t` to the nearest of the `sorted` stamps.
fn nearest(sorted: &[f64], t: f64) -> Option<f64> {
    let i = sorted.partition_point(|&s| s < t);
    [i.checked_sub(1), Some(i)]
        .into_iter()
        .flatten()
        .filter_map(|j| sorted.get(j))
        .map(|s| s - t)
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
}

/// The estimate's step when the reference counts frames (whole numbers, step 1) and the
/// estimate's stamps are less than half a second apart.
fn frame_index_scale(estimate: &[f64], reference: &[f64]) -> Option<f64> {
    let whole = reference.len() >= 3 && reference.iter().all(|t| t.fract() == 0.0);
    if !whole || median_step(reference) != Some(1.0) {
        return None;
    }
    median_step(estimate).filter(|s| *s < 0.5).map(simplest)
}

/// (factor, scale) when the reference's span is a power of ten times the estimate's.
fn power_of_ten(estimate_span: f64, reference_span: f64) -> Option<(f64, f64)> {
    if !(estimate_span > 0.0 && reference_span > 0.0) {
        return None;
    }
    let ratio = reference_span / estimate_span;
    POWERS_OF_TEN
        .into_iter()
        .find(|(factor, _)| (ratio / factor - 1.0).abs() <= RATIO_TOLERANCE)
}

/// The offset to add to the reference when its stamps sit a constant time (more than
/// `max_diff`) from the estimate's: the median time from each estimated stamp to the nearest
/// reference stamp, when nearly all of them agree.
fn constant_shift(estimate: &[f64], reference: &[f64], max_diff: f64) -> Option<f64> {
    let mut sorted: Vec<f64> = reference
        .iter()
        .copied()
        .filter(|t| t.is_finite())
        .collect();
    sorted.sort_by(f64::total_cmp);
    let diffs: Vec<f64> = estimate
        .iter()
        .filter_map(|&t| nearest(&sorted, t))
        .collect();
    let shift = median(diffs.clone())?;
    let spread = median(diffs.iter().map(|d| (d - shift).abs()).collect())?;
    (shift.abs() > max_diff && spread <= max_diff).then(|| round_offset(-shift, max_diff))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seq(n: usize, start: f64, step: f64) -> Vec<f64> {
        (0..n).map(|i| start + i as f64 * step).collect()
    }

    #[test]
    fn frame_indices_suggest_the_estimate_step() {
        let cause = diagnose(&seq(154, 0.0, 0.1), &seq(154, 0.0, 1.0), 0.01);
        assert_eq!(
            cause,
            LikelyCause::FrameIndices {
                scale: 0.1,
                offset_s: 0.0
            }
        );
        assert_eq!(cause.fix(), Some(StampMap::new(0.1, 0.0).unwrap()));
        // An estimate on the Unix epoch also needs the offset.
        let epoch = diagnose(&seq(154, 1.6e9, 0.1), &seq(154, 0.0, 1.0), 0.01);
        assert_eq!(
            epoch.fix(),
            Some(StampMap {
                scale: 0.1,
                offset_s: 1.6e9
            })
        );
        assert!(epoch.to_string().contains("frame indices"), "{epoch}");
    }

    #[test]
    fn a_power_of_ten_names_the_unit() {
        for (factor, scale, unit) in [(1e3, 1e-3, "milli"), (1e6, 1e-6, "micro")] {
            let cause = diagnose(&seq(100, 0.0, 0.1), &seq(100, 0.0, 0.1 * factor), 0.01);
            assert_eq!(
                cause,
                LikelyCause::PowerOfTen {
                    factor,
                    scale,
                    offset_s: 0.0
                }
            );
            assert!(cause.to_string().contains(unit), "{cause}");
        }
        // Nanoseconds since the epoch against seconds since the start: scale, then offset.
        let ns = diagnose(&seq(100, 0.0, 0.1), &seq(100, 1.6e18, 1e8), 0.01);
        let fix = ns.fix().unwrap();
        assert_eq!(fix.scale, 1e-9);
        assert!((fix.offset_s + 1.6e9).abs() < 1e-3, "{fix:?}");
    }

    #[test]
    fn apart_ranges_suggest_the_offset() {
        let cause = diagnose(&seq(100, 0.0, 0.1), &seq(100, 1234.5, 0.1), 0.01);
        assert_eq!(cause, LikelyCause::Offset { offset_s: -1234.5 });
        assert!(
            cause.to_string().contains("starts 1234.500 s before"),
            "{cause}"
        );
        // Equally long ranges that overlap only partly are offset too.
        let partly = diagnose(&seq(100, 0.0, 0.1), &seq(100, -5.0, 0.1), 0.01);
        assert_eq!(partly, LikelyCause::Offset { offset_s: 5.0 });
    }

    #[test]
    fn a_constant_shift_within_the_range_is_found() {
        let cause = diagnose(
            &seq(100, 0.0, 0.1),
            &seq(120, -1.0, 0.1)
                .iter()
                .map(|t| t + 0.03)
                .collect::<Vec<_>>(),
            0.01,
        );
        assert_eq!(cause, LikelyCause::Shift { offset_s: -0.03 });
    }

    #[test]
    fn a_short_or_sparse_reference_has_no_fix() {
        let short = diagnose(&seq(100, 0.0, 0.1), &seq(30, 0.0, 0.1), 0.01);
        assert!(
            matches!(short, LikelyCause::ShortReference { covered } if (covered - 0.29).abs() < 0.01)
        );
        assert_eq!(short.fix(), None);
        let sparse = diagnose(
            &seq(100, 0.0, 0.1),
            &seq(11, 0.0, 1.0)
                .iter()
                .map(|t| t + 0.05)
                .collect::<Vec<_>>(),
            0.01,
        );
        assert!(
            matches!(sparse, LikelyCause::SparseReference { .. }),
            "{sparse:?}"
        );
    }

    #[test]
    fn a_cause_is_named_only_when_its_fix_pairs_the_poses() {
        // A 1 Hz reference on whole seconds looks like frame indices, but scaling it by 0.1
        // would pair almost nothing: it is sparse.
        let cause = diagnose(&seq(154, 0.0, 0.1), &seq(16, 0.0, 1.0), 0.01);
        assert!(
            matches!(cause, LikelyCause::SparseReference { .. }),
            "{cause:?}"
        );
        assert_eq!(cause.fix(), None);
    }
}
