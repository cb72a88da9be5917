//! Which fields of a point file feed which channel of a [`crate::cloud::RawCloud`], and the
//! units of time and range.

use serde::{Deserialize, Serialize};

/// A per-point quantity read from point files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// x, metres.
    X,
    /// y, metres.
    Y,
    /// z, metres.
    Z,
    /// Intensity or signal.
    Intensity,
    /// Calibrated reflectivity.
    Reflectivity,
    /// Ambient / near-infrared light.
    NearIr,
    /// Measured range (unit: [`RangeUnit`]).
    Range,
    /// Beam index.
    Ring,
    /// Per-point firing time (unit: [`TimeUnit`]).
    Time,
}

/// Number of [`Slot`]s.
pub const SLOTS: usize = 9;

/// Field names read, in order of preference within a slot; matched ignoring case. A file
/// with both `intensity` and `signal` feeds intensity from `intensity` and ignores `signal`.
pub const FIELD_NAMES: [(&str, Slot); 14] = [
    ("x", Slot::X),
    ("y", Slot::Y),
    ("z", Slot::Z),
    ("intensity", Slot::Intensity),
    ("signal", Slot::Intensity),
    ("reflectivity", Slot::Reflectivity),
    ("ambient", Slot::NearIr),
    ("near_ir", Slot::NearIr),
    ("nir", Slot::NearIr),
    ("range", Slot::Range),
    ("ring", Slot::Ring),
    ("t", Slot::Time),
    ("time", Slot::Time),
    ("timestamp", Slot::Time),
];

/// Position of `name` in [`FIELD_NAMES`], ignoring case (called per value while parsing,
/// so exact lower-case names take a fast path).
pub fn alias_index(name: &str) -> Option<usize> {
    FIELD_NAMES
        .iter()
        .position(|(n, _)| *n == name)
        .or_else(|| {
            FIELD_NAMES
                .iter()
                .position(|(n, _)| n.eq_ignore_ascii_case(name))
        })
}

/// Unit of the per-point time field.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum TimeUnit {
    /// Decided per file from the span of its times: ≤ 10 → seconds, ≤ 1e7 → microseconds,
    /// else nanoseconds (when every point has the same time: its magnitude, ≥ 1e17 ns,
    /// ≥ 1e14 µs, else s).
    #[default]
    Auto,
    /// Seconds.
    S,
    /// Microseconds.
    Us,
    /// Nanoseconds (Ouster's `t`).
    Ns,
}

/// Unit of the range field.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum RangeUnit {
    /// Millimetres when the field is an integer (Ouster publishes `range` as u32 mm),
    /// metres when it is a float.
    #[default]
    Auto,
    /// Metres.
    M,
    /// Millimetres.
    Mm,
}

/// The unit settings of a point-file source.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FieldOptions {
    /// Unit of the per-point time.
    pub time_unit: TimeUnit,
    /// Unit of the range field.
    pub range_unit: RangeUnit,
}

/// One field of a point file as its header declares it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldInfo {
    /// Field name.
    pub name: String,
    /// True for integer types.
    pub integer: bool,
    /// Values per point (PCD `COUNT`; 1 for PLY scalars, 0 for PLY lists).
    pub count: usize,
}

/// Which field (by position in the file's field list) feeds each [`Slot`].
/// Why a file's fields cannot be read as points.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FieldError {
    /// A field keylo reads holds several values per point.
    #[error("field `{field}` holds {count} values per point; keylo reads it as one number")]
    MultiValue { field: String, count: usize },
    /// No x, y or z field.
    #[error("no field `{}` (expected x, y, z; the file has: {})", missing.join("`, `"), if available.is_empty() { "none".to_string() } else { available.join(", ") })]
    Missing {
        missing: Vec<String>,
        available: Vec<String>,
    },
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldMap {
    source: [Option<usize>; SLOTS],
    integer: [bool; SLOTS],
    /// Names of the fields that feed no slot (reported, not read).
    pub ignored: Vec<String>,
}

impl FieldMap {
    /// Maps `fields`; the error names what is missing (x, y, z) or unusable (a read field
    /// that is a list or has several values per point).
    pub fn new(fields: &[FieldInfo]) -> Result<Self, FieldError> {
        let mut source = [None; SLOTS];
        let mut integer = [false; SLOTS];
        for (_, slot) in FIELD_NAMES {
            let s = slot as usize;
            if source[s].is_some() {
                continue;
            }
            let found = FIELD_NAMES
                .iter()
                .filter(|(_, sl)| *sl == slot)
                .find_map(|(n, _)| fields.iter().position(|f| f.name.eq_ignore_ascii_case(n)));
            if let Some(pos) = found {
                let f = &fields[pos];
                if f.count != 1 {
                    return Err(FieldError::MultiValue {
                        field: f.name.clone(),
                        count: f.count,
                    });
                }
                source[s] = Some(pos);
                integer[s] = f.integer;
            }
        }
        let missing: Vec<&str> = ["x", "y", "z"]
            .into_iter()
            .zip(&source)
            .filter(|(_, s)| s.is_none())
            .map(|(n, _)| n)
            .collect();
        if !missing.is_empty() {
            return Err(FieldError::Missing {
                missing: missing.iter().map(|m| m.to_string()).collect(),
                available: fields.iter().map(|f| f.name.clone()).collect(),
            });
        }
        let ignored = (0..fields.len())
            .filter(|p| !source.contains(&Some(*p)))
            .map(|p| fields[p].name.clone())
            .collect();
        Ok(Self {
            source,
            integer,
            ignored,
        })
    }

    /// Position of the field that feeds `slot`.
    pub fn field(&self, slot: Slot) -> Option<usize> {
        self.source[slot as usize]
    }

    /// True when the field feeding `slot` is an integer type.
    pub fn is_integer(&self, slot: Slot) -> bool {
        self.integer[slot as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(names: &[&str]) -> Vec<FieldInfo> {
        names
            .iter()
            .map(|n| FieldInfo {
                name: n.to_string(),
                integer: *n == "range",
                count: 1,
            })
            .collect()
    }

    #[test]
    fn common_names_map_and_the_rest_is_ignored() {
        let f = info(&["X", "y", "z", "signal", "intensity", "t", "range", "rgb"]);
        let m = FieldMap::new(&f).unwrap();
        assert_eq!(m.field(Slot::X), Some(0));
        assert_eq!(m.field(Slot::Intensity), Some(4));
        assert_eq!(m.field(Slot::Time), Some(5));
        assert!(m.is_integer(Slot::Range));
        assert_eq!(m.field(Slot::Ring), None);
        assert_eq!(m.ignored, vec!["signal".to_string(), "rgb".to_string()]);
    }

    #[test]
    fn missing_coordinates_and_vector_fields_are_errors() {
        let e = FieldMap::new(&info(&["x", "intensity"]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no field `y`, `z`") && e.contains("x, intensity"),
            "{e}"
        );
        let mut f = info(&["x", "y", "z"]);
        f[2].count = 3;
        assert!(FieldMap::new(&f)
            .unwrap_err()
            .to_string()
            .contains("field `z` holds 3 values"));
    }
}
