//! Detector/descriptor combinations by name: `AKAZE_AKAZE`, `FAST_BRIEF`, `SUPERPOINT`, a
//! plugin's `plugin:NAME_BRIEF`, the paper's list or every valid pair the registry offers.

use keylo_core::Registry;

use crate::KpEvalError;

/// The paper's names for registry kinds.
const TOKENS: &[(&str, &str)] = &[
    ("AKAZE", "akaze"),
    ("BRIEF", "brief"),
    ("BRISK", "brisk"),
    ("FAST", "fast"),
    ("FREAK", "freak"),
    ("HARRIS", "harris"),
    ("KAZE", "kaze"),
    ("ORB", "orb"),
    ("SHITOMASI", "shi-tomasi"),
    ("SIFT", "sift"),
    ("SUPERPOINT", "superpoint"),
    ("SURF", "surf"),
];

/// The combinations of the paper's figures 3–6 (its SuperPoint is `SUPERPOINT`).
pub const PAPER: &[&str] = &[
    "AKAZE_AKAZE",
    "BRISK_BRIEF",
    "BRISK_BRISK",
    "BRISK_FREAK",
    "BRISK_SIFT",
    "BRISK_SURF",
    "FAST_BRIEF",
    "FAST_BRISK",
    "FAST_FREAK",
    "FAST_SIFT",
    "FAST_SURF",
    "HARRIS_BRIEF",
    "HARRIS_BRISK",
    "HARRIS_FREAK",
    "HARRIS_SIFT",
    "HARRIS_SURF",
    "ORB_ORB",
    "SHITOMASI_BRIEF",
    "SHITOMASI_BRISK",
    "SHITOMASI_FREAK",
    "SHITOMASI_SIFT",
    "SHITOMASI_SURF",
    "SIFT_BRIEF",
    "SIFT_BRISK",
    "SIFT_FREAK",
    "SIFT_SIFT",
    "SIFT_SURF",
    "SURF_BRIEF",
    "SURF_BRISK",
    "SURF_SIFT",
    "SURF_SURF",
    "SUPERPOINT",
];

/// Descriptors that describe keypoints of any detector (`all` pairs every detector with
/// them; AKAZE, KAZE and SuperPoint describe their own keypoints only, or by explicit name).
const GENERIC_DESCRIPTORS: &[&str] = &["brief", "brisk", "freak", "orb", "sift", "surf"];

/// Pairs `all` leaves out: ORB describes octaves 0–7 only and SIFT packs octave and layer
/// into its keypoints' octave (named explicitly, the pair is an error that says so).
const INCOMPATIBLE: &[(&str, &str)] = &[("sift", "orb")];

/// Which combinations to evaluate.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ComboSet {
    /// The paper's 32 (those this build cannot run are skipped with the reason).
    Paper,
    /// Every registered detector with its own descriptor and every generic descriptor.
    All,
    /// Named combinations (each must run).
    Named(Vec<String>),
}

impl ComboSet {
    /// `paper`, `all`, or a comma-separated list of names.
    pub fn parse(spec: &str) -> Self {
        match spec.trim() {
            "paper" => Self::Paper,
            "all" => Self::All,
            list => Self::Named(
                list.split(',')
                    .map(str::trim)
                    .filter(|s| !s.is_empty())
                    .map(String::from)
                    .collect(),
            ),
        }
    }

    /// Whether a combination this build cannot construct is skipped (`paper`, `all`) rather
    /// than an error (a named list).
    pub fn skips_unavailable(&self) -> bool {
        !matches!(self, Self::Named(_))
    }
}

/// One detector/descriptor pair.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Combo {
    /// `DETECTOR_DESCRIPTOR` in the paper's spelling (`SHITOMASI_BRIEF`).
    pub name: String,
    /// Registry kind of the detector.
    pub detector: String,
    /// Registry kind of the descriptor (the detector's own when equal).
    pub descriptor: String,
}

impl Combo {
    /// Detector and descriptor are one backend (described in the detection pass when it can).
    pub fn own_descriptor(&self) -> bool {
        self.detector == self.descriptor
    }

    /// The paper's name of the detector (`SHITOMASI`).
    pub fn detector_name(&self) -> String {
        token_of(&self.detector)
    }

    fn new(detector: &str, descriptor: &str) -> Self {
        Self {
            name: format!("{}_{}", token_of(detector), token_of(descriptor)),
            detector: detector.into(),
            descriptor: descriptor.into(),
        }
    }
}

/// The registry kind a name token stands for (the paper's spelling or the kind itself).
fn kind_of(token: &str) -> String {
    let upper = token.to_ascii_uppercase();
    TOKENS
        .iter()
        .find(|(t, _)| *t == upper)
        .map_or_else(|| token.to_string(), |(_, k)| (*k).to_string())
}

/// The paper's spelling of a registry kind (plugins keep their kind).
fn token_of(kind: &str) -> String {
    TOKENS
        .iter()
        .find(|(_, k)| *k == kind)
        .map_or_else(|| kind.to_string(), |(t, _)| (*t).to_string())
}

/// The combinations of `set`, checked against `registry`.
pub fn parse_combos(set: &ComboSet, registry: &Registry) -> Result<Vec<Combo>, KpEvalError> {
    match set {
        ComboSet::Paper => PAPER.iter().map(|n| parse_one(n, registry)).collect(),
        ComboSet::All => Ok(all(registry)),
        ComboSet::Named(names) => {
            if names.is_empty() {
                return Err(KpEvalError::Combo {
                    name: String::new(),
                    message:
                        "no combination named: expected e.g. AKAZE_AKAZE,ORB_ORB, `paper` or `all`"
                            .into(),
                });
            }
            let mut out: Vec<Combo> = Vec::new();
            for n in names {
                let c = parse_one(n, registry)?;
                if !out.contains(&c) {
                    out.push(c);
                }
            }
            Ok(out)
        }
    }
}

fn all(registry: &Registry) -> Vec<Combo> {
    let descriptors = registry.descriptors.kinds();
    let mut out = Vec::new();
    for det in registry.detectors.kinds() {
        if descriptors.contains(&det) {
            out.push(Combo::new(det, det));
        }
        for g in GENERIC_DESCRIPTORS {
            if *g != det && descriptors.contains(g) && !INCOMPATIBLE.contains(&(det, *g)) {
                out.push(Combo::new(det, g));
            }
        }
    }
    out
}

/// `DET_DES` or `DET` (its own descriptor); a plugin kind may hold `_`, so every split is tried.
fn parse_one(name: &str, registry: &Registry) -> Result<Combo, KpEvalError> {
    let is_det = |t: &str| registry.detectors.get(&kind_of(t)).is_some();
    let is_des = |t: &str| registry.descriptors.get(&kind_of(t)).is_some();
    let name = name.trim();
    if is_det(name) {
        let kind = kind_of(name);
        if !is_des(name) {
            return Err(KpEvalError::Combo {
                name: name.into(),
                message: format!(
                    "detector `{kind}` has no descriptor of its own: name one, e.g. {}_BRIEF",
                    token_of(&kind)
                ),
            });
        }
        return Ok(Combo::new(&kind, &kind));
    }
    for (i, _) in name.match_indices('_') {
        let (det, des) = (&name[..i], &name[i + 1..]);
        if is_det(det) && is_des(des) {
            return Ok(Combo::new(&kind_of(det), &kind_of(des)));
        }
    }
    Err(KpEvalError::Combo {
        name: name.into(),
        message: format!(
            "expected DETECTOR_DESCRIPTOR; detectors: {}; descriptors: {}",
            registry.detectors.kinds().join(", "),
            registry.descriptors.kinds().join(", ")
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn registry() -> Registry {
        let mut r = Registry::default();
        keylo_features::register(&mut r);
        r
    }

    #[test]
    fn names_map_to_kinds_both_ways() {
        let r = registry();
        let c = parse_combos(&ComboSet::parse("SHITOMASI_BRIEF, akaze,SUPERPOINT"), &r).unwrap();
        assert_eq!(c[0].detector, "shi-tomasi");
        assert_eq!(c[0].descriptor, "brief");
        assert_eq!(c[0].name, "SHITOMASI_BRIEF");
        assert_eq!(c[1].name, "AKAZE_AKAZE");
        assert!(c[1].own_descriptor());
        assert_eq!(c[2].name, "SUPERPOINT_SUPERPOINT");
        let paper = parse_combos(&ComboSet::Paper, &r).unwrap();
        assert_eq!(paper.len(), 32);
        let all = parse_combos(&ComboSet::All, &r).unwrap();
        assert!(all.len() > 40, "{}", all.len());
        assert!(all.iter().any(|c| c.name == "ORB_FREAK"));
        assert!(!all.iter().any(|c| c.name == "FAST_AKAZE"));
    }

    #[test]
    fn unknown_names_list_what_exists() {
        let r = registry();
        let e = parse_combos(&ComboSet::parse("FAST_NOPE"), &r)
            .unwrap_err()
            .to_string();
        assert!(e.contains("FAST_NOPE") && e.contains("descriptors:"), "{e}");
        let e = parse_combos(&ComboSet::parse("FAST"), &r)
            .unwrap_err()
            .to_string();
        assert!(e.contains("FAST_BRIEF"), "{e}");
        assert!(parse_combos(&ComboSet::parse(" , "), &r).is_err());
    }
}
