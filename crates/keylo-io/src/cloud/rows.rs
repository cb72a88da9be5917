//! A point's image row from its elevation: the beam of nearest elevation, found through a
//! lookup table instead of a search (the projection runs once per point of every scan).

/// Elevation → row for a beam table (altitudes descending, top row first).
#[derive(Debug, Clone)]
pub(crate) struct RowLookup {
    altitudes: Vec<f64>,
    /// Elevations beyond `[low, high]` (half a beam spacing outside the table) have no row.
    low: f64,
    high: f64,
    /// Bins per degree.
    scale: f64,
    /// Per bin, the first and last row that can be nearest to an elevation in it.
    bins: Vec<(u16, u16)>,
    /// The same over `sin(elevation)` (what a point gives without `asin`): the one row of
    /// the bin, or [`AMBIGUOUS`] when the bin holds a boundary or an end of the table.
    sin_low: f64,
    sin_scale: f64,
    sin_bins: Vec<u16>,
}

/// A `sin_bins` entry that needs the elevation itself.
const AMBIGUOUS: u16 = u16::MAX;

/// Bins of the table: fine enough that nearly every bin has one candidate row.
const BINS: usize = 4096;

impl RowLookup {
    /// The lookup of `altitudes` (degrees, descending; at most 65 536 rows).
    pub(crate) fn new(altitudes: Vec<f64>) -> Self {
        let (top, bottom) = match (altitudes.first(), altitudes.last()) {
            (Some(&t), Some(&b)) => (t, b),
            _ => (0.0, 0.0),
        };
        let margin = if altitudes.len() > 1 {
            0.5 * (top - bottom) / (altitudes.len() - 1) as f64
        } else {
            0.5
        };
        let (low, high) = (bottom - margin, top + margin);
        let scale = BINS as f64 / (high - low).max(1e-9);
        let sin = |deg: f64| deg.clamp(-90.0, 90.0).to_radians().sin();
        let (sin_low, sin_high) = (sin(low), sin(high));
        let mut lookup = Self {
            altitudes,
            low,
            high,
            scale,
            bins: Vec::new(),
            sin_low,
            sin_scale: BINS as f64 / (sin_high - sin_low).max(1e-12),
            sin_bins: Vec::new(),
        };
        let width = 1.0 / scale;
        lookup.bins = (0..BINS)
            .map(|b| {
                let lo = low + b as f64 * width;
                // One bin of slack on both sides: an elevation rounded into a neighbouring
                // bin still finds its row among the candidates.
                let first = lookup.nearest(lo + 2.0 * width);
                let last = lookup.nearest(lo - width);
                (first as u16, last as u16)
            })
            .collect();
        let width = (sin_high - sin_low) / BINS as f64;
        let degrees = |s: f64| s.clamp(-1.0, 1.0).asin().to_degrees();
        lookup.sin_bins = (0..BINS)
            .map(|b| {
                let lo = sin_low + b as f64 * width;
                let first = lookup.nearest(degrees(lo + 2.0 * width));
                let last = lookup.nearest(degrees(lo - width));
                let interior = b > 1 && b + 2 < BINS;
                if interior && first == last {
                    first as u16
                } else {
                    AMBIGUOUS
                }
            })
            .collect();
        lookup
    }

    /// The row of a point whose `z / ‖p‖` is `sin_elevation`: [`Self::row`] of its
    /// elevation, with `asin` only for points near a beam boundary or the table's ends.
    #[inline]
    pub(crate) fn row_of_sin(&self, sin_elevation: f64) -> Option<usize> {
        let bin = (sin_elevation - self.sin_low) * self.sin_scale;
        if bin >= 0.0 && bin < BINS as f64 {
            let row = self.sin_bins[bin as usize];
            if row != AMBIGUOUS {
                return Some(usize::from(row));
            }
        }
        self.row(sin_elevation.asin().to_degrees())
    }

    /// The row of the nearest beam; `None` beyond half a beam spacing outside the table.
    #[inline]
    pub(crate) fn row(&self, elevation_deg: f64) -> Option<usize> {
        if !(elevation_deg <= self.high && elevation_deg >= self.low) {
            return None;
        }
        let bin = (((elevation_deg - self.low) * self.scale) as usize).min(BINS - 1);
        let (first, last) = self.bins[bin];
        let a = &self.altitudes;
        let mut best = usize::from(first);
        for r in usize::from(first) + 1..=usize::from(last) {
            if (a[r] - elevation_deg).abs() < (a[best] - elevation_deg).abs() {
                best = r;
            }
        }
        Some(best)
    }

    /// The nearest row by search (ties: the upper beam), for any elevation.
    fn nearest(&self, elevation_deg: f64) -> usize {
        let a = &self.altitudes;
        let below = a.partition_point(|&x| x > elevation_deg);
        let candidates = [below.checked_sub(1), Some(below).filter(|&b| b < a.len())];
        candidates
            .into_iter()
            .flatten()
            .min_by(|&x, &y| {
                (a[x] - elevation_deg)
                    .abs()
                    .total_cmp(&(a[y] - elevation_deg).abs())
            })
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// KITTI's HDL-64E-like table: two blocks of different spacing.
    fn uneven() -> Vec<f64> {
        let mut a: Vec<f64> = (0..32).map(|i| 2.0 - i as f64 / 3.0).collect();
        a.extend((0..32).map(|i| -8.83 - i as f64 * 0.5));
        a
    }

    #[test]
    fn the_table_gives_the_searched_row_everywhere() {
        for altitudes in [
            uneven(),
            (0..64).map(|i| 3.0 - i as f64 * 28.0 / 63.0).collect(),
        ] {
            let l = RowLookup::new(altitudes.clone());
            let mut e = -30.0;
            while e < 8.0 {
                let want = (e <= l.high && e >= l.low).then(|| l.nearest(e));
                assert_eq!(l.row(e), want, "elevation {e}");
                // Midpoints between beams (ties) and their neighbours.
                e += 0.000_731;
            }
            let mut s = -0.6;
            while s < 0.2 {
                assert_eq!(l.row_of_sin(s), l.row(s.asin().to_degrees()), "sin {s}");
                s += 0.000_011_3;
            }
            for w in altitudes.windows(2) {
                let mid = 0.5 * (w[0] + w[1]);
                for m in [mid, mid.next_up(), mid.next_down()] {
                    assert_eq!(l.row(m), Some(l.nearest(m)), "midpoint {m}");
                    let s = m.to_radians().sin();
                    assert_eq!(l.row_of_sin(s), l.row(s.asin().to_degrees()), "sin {s}");
                }
            }
        }
    }

    #[test]
    fn one_beam_and_outside() {
        let l = RowLookup::new(vec![0.0]);
        assert_eq!(l.row(0.4), Some(0));
        assert_eq!(l.row(0.6), None);
        assert_eq!(l.row(f64::NAN), None);
    }
}
