//! Per-point values gathered field by field, then turned into a [`RawCloud`] with units
//! applied.

use super::fields::{FieldMap, FieldOptions, RangeUnit, Slot, TimeUnit, SLOTS};
use crate::cloud::RawCloud;

/// Seconds above which per-point times are an absolute clock (about 11.6 days: no sweep lasts
/// that long).
const ABSOLUTE_TIME_S: f64 = 1e6;

/// The values of the mapped fields of one file, one column per [`Slot`].
#[derive(Debug, Clone)]
pub struct Columns {
    map: FieldMap,
    values: [Option<Vec<f64>>; SLOTS],
}

impl Columns {
    /// Empty columns for the fields of `map`, room for `capacity` points.
    pub fn new(map: &FieldMap, capacity: usize) -> Self {
        let all = [
            Slot::X,
            Slot::Y,
            Slot::Z,
            Slot::Intensity,
            Slot::Reflectivity,
            Slot::NearIr,
            Slot::Range,
            Slot::Ring,
            Slot::Time,
        ];
        let values = all.map(|s| map.field(s).map(|_| Vec::with_capacity(capacity)));
        Self {
            map: map.clone(),
            values,
        }
    }

    /// The field map the columns follow.
    pub fn map(&self) -> &FieldMap {
        &self.map
    }

    /// Appends one point; `value(p)` is the value of the field at position `p`.
    pub fn push(&mut self, value: impl Fn(usize) -> f64) {
        let map = &self.map;
        for (s, column) in self.values.iter_mut().enumerate() {
            if let Some(column) = column {
                let slot = slot_of(s);
                if let Some(p) = map.field(slot) {
                    column.push(value(p));
                }
            }
        }
    }

    /// Number of points gathered.
    pub fn len(&self) -> usize {
        self.values[0].as_ref().map_or(0, Vec::len)
    }

    /// True when no point was gathered.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The cloud: units applied, per-point times relative to the cloud time. The cloud time
    /// is `stamp`, or the earliest point time when the points carry an absolute clock. The
    /// error names the field whose values are unusable.
    pub fn finish(
        self,
        stamp: f64,
        grid: Option<(usize, usize)>,
        options: &FieldOptions,
    ) -> Result<RawCloud, String> {
        let range_integer = self.map.is_integer(Slot::Range);
        let [x, y, z, intensity, reflectivity, near_ir, range, ring, time] = self.values;
        let (x, y, z) = (
            x.unwrap_or_default(),
            y.unwrap_or_default(),
            z.unwrap_or_default(),
        );
        let points = x
            .iter()
            .zip(&y)
            .zip(&z)
            .map(|((x, y), z)| [*x as f32, *y as f32, *z as f32])
            .collect();
        let range_scale = match options.range_unit {
            RangeUnit::M => 1.0,
            RangeUnit::Mm => 1e-3,
            RangeUnit::Auto if range_integer => 1e-3,
            RangeUnit::Auto => 1.0,
        };
        let (timestamp, time) = match time {
            Some(t) => {
                let (t0, rel) = point_times(t, stamp, options.time_unit);
                (t0, Some(rel))
            }
            None => (stamp, None),
        };
        let cloud = RawCloud {
            timestamp,
            points,
            intensity: intensity.map(to_f32),
            reflectivity: reflectivity.map(to_f32),
            near_ir: near_ir.map(to_f32),
            range: range.map(|r| r.iter().map(|v| (v * range_scale) as f32).collect()),
            ring: ring.map(|r| rings(&r)).transpose()?,
            time,
            grid,
        };
        cloud.check().map_err(|e| e.to_string())?;
        Ok(cloud)
    }
}

fn slot_of(index: usize) -> Slot {
    match index {
        0 => Slot::X,
        1 => Slot::Y,
        2 => Slot::Z,
        3 => Slot::Intensity,
        4 => Slot::Reflectivity,
        5 => Slot::NearIr,
        6 => Slot::Range,
        7 => Slot::Ring,
        _ => Slot::Time,
    }
}

fn to_f32(v: Vec<f64>) -> Vec<f32> {
    v.into_iter().map(|x| x as f32).collect()
}

fn rings(values: &[f64]) -> Result<Vec<u16>, String> {
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            if v.fract() == 0.0 && (0.0..=f64::from(u16::MAX)).contains(&v) {
                Ok(v as u16)
            } else {
                Err(format!(
                    "field `ring`: value {v} of point {i} is not a beam index (0..=65535)"
                ))
            }
        })
        .collect()
}

/// The cloud time and the per-point times in seconds relative to it.
fn point_times(t: Vec<f64>, stamp: f64, unit: TimeUnit) -> (f64, Vec<f64>) {
    let finite = t.iter().copied().filter(|v| v.is_finite());
    let (min, max) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if min > max {
        return (stamp, t);
    }
    let per_second = match unit {
        TimeUnit::S => 1.0,
        TimeUnit::Us => 1e6,
        TimeUnit::Ns => 1e9,
        TimeUnit::Auto => auto_per_second(min, max),
    };
    if min / per_second >= ABSOLUTE_TIME_S {
        // Subtract in the file's unit first: epoch nanoseconds lose precision as seconds.
        let rel = t.iter().map(|v| (v - min) / per_second).collect();
        (min / per_second, rel)
    } else {
        (stamp, t.iter().map(|v| v / per_second).collect())
    }
}

/// Units per second, chosen from the span of one sweep's times (a sweep lasts between about
/// a millisecond and ten seconds), or from the magnitude when every time is the same.
fn auto_per_second(min: f64, max: f64) -> f64 {
    let span = max - min;
    let m = min.abs().max(max.abs());
    if span > 0.0 {
        if span <= 10.0 {
            1.0
        } else if span <= 1e7 {
            1e6
        } else {
            1e9
        }
    } else if m >= 1e17 {
        1e9
    } else if m >= 1e14 {
        1e6
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::folder::fields::FieldInfo;

    fn map(names: &[(&str, bool)]) -> FieldMap {
        let f: Vec<FieldInfo> = names
            .iter()
            .map(|(n, int)| FieldInfo {
                name: n.to_string(),
                integer: *int,
                count: 1,
            })
            .collect();
        FieldMap::new(&f).unwrap()
    }

    #[test]
    fn ouster_units_become_seconds_and_metres() {
        let m = map(&[
            ("x", false),
            ("y", false),
            ("z", false),
            ("t", true),
            ("range", true),
        ]);
        let mut c = Columns::new(&m, 2);
        c.push(|p| [1.0, 2.0, 3.0, 0.0, 3742.0][p]);
        c.push(|p| [1.0, 2.0, 3.0, 99_000_000.0, 1000.0][p]);
        let cloud = c.finish(5.0, None, &FieldOptions::default()).unwrap();
        assert_eq!(cloud.timestamp, 5.0);
        let t = cloud.time.unwrap();
        assert!((t[1] - 0.099).abs() < 1e-12);
        assert_eq!(cloud.range.unwrap(), vec![3.742, 1.0]);
        assert_eq!(cloud.points[0], [1.0, 2.0, 3.0]);
    }

    #[test]
    fn absolute_times_set_the_cloud_time() {
        let m = map(&[
            ("x", false),
            ("y", false),
            ("z", false),
            ("timestamp", false),
        ]);
        let mut c = Columns::new(&m, 2);
        c.push(|p| [0.0, 0.0, 0.0, 1_700_000_000_100_000_000.0][p]);
        c.push(|p| [0.0, 0.0, 0.0, 1_700_000_000_000_000_000.0][p]);
        let cloud = c.finish(0.0, None, &FieldOptions::default()).unwrap();
        assert_eq!(cloud.timestamp, 1_700_000_000.0);
        let t = cloud.time.unwrap();
        assert!((t[0] - 0.1).abs() < 1e-9, "{t:?}");
        let opts = FieldOptions {
            time_unit: TimeUnit::Us,
            ..FieldOptions::default()
        };
        let mut c = Columns::new(&m, 1);
        c.push(|p| [0.0, 0.0, 0.0, 50_000.0][p]);
        let cloud = c.finish(2.0, None, &opts).unwrap();
        assert_eq!((cloud.timestamp, cloud.time.unwrap()), (2.0, vec![0.05]));
    }

    #[test]
    fn auto_units_by_span() {
        assert_eq!(auto_per_second(0.0, 0.1), 1.0);
        assert_eq!(auto_per_second(0.0, 1e5), 1e6);
        assert_eq!(auto_per_second(0.0, 1e8), 1e9);
        assert_eq!(auto_per_second(1.7e18, 1.7e18), 1e9);
        assert_eq!(auto_per_second(0.0, 0.0), 1.0);
    }

    #[test]
    fn bad_rings_name_the_point() {
        let m = map(&[("x", false), ("y", false), ("z", false), ("ring", false)]);
        let mut c = Columns::new(&m, 1);
        c.push(|p| [0.0, 0.0, 0.0, 1.5][p]);
        let e = c.finish(0.0, None, &FieldOptions::default()).unwrap_err();
        assert!(e.contains("value 1.5 of point 0"), "{e}");
    }
}
