//! Building the detectors and descriptors of a set of combinations from a [`Registry`], one
//! group per detector so each detector runs once per image for all its combinations.

use keylo_core::registry::Factory;
use keylo_core::{BuildContext, ConfigError, CoreError, Descriptor, Detector, Registry};

use crate::{Combo, Definitions, EvalSpec, KpEvalError, Preset};

/// How a combination gets its descriptors.
pub enum Describer {
    /// The detector's own detect-and-compute pass (AKAZE_AKAZE, ORB_ORB, SUPERPOINT, …), as
    /// keylo's pipeline runs it.
    OwnPass,
    /// A separate descriptor computed on the detector's keypoints.
    Separate(Box<dyn Descriptor>),
}

/// One detector and every combination that uses it.
pub struct Group {
    /// Registry kind of the detector.
    pub detector_kind: String,
    /// The paper's name of the detector.
    pub detector_name: String,
    pub detector: Box<dyn Detector>,
    pub combos: Vec<(Combo, Describer)>,
    /// Whose metric definitions the group follows.
    pub definitions: Definitions,
}

/// The authors' SuperPoint script for SuperPoint under the `paper` preset, their C++
/// program otherwise.
fn definitions(detector_kind: &str, preset: Preset) -> Definitions {
    if preset == Preset::Paper && detector_kind == "superpoint" {
        Definitions::SuperPointScript
    } else {
        Definitions::Program
    }
}

/// The combinations that could not be built, with the reason.
pub type Skipped = Vec<(String, String)>;

/// A backend of `kind` from its parameters (checked and completed first).
fn build<T: ?Sized>(
    factory: &dyn Factory<T>,
    params: &toml::Table,
    kind: &str,
    ctx: &BuildContext,
) -> Result<Box<T>, CoreError> {
    let resolved = factory.resolve(params).map_err(|(path, message)| {
        CoreError::Config(ConfigError::Invalid {
            origin: format!("params.{kind}"),
            path,
            message,
        })
    })?;
    factory.build(&resolved, ctx)
}

/// Whether a backend's parameter schema has `key`.
fn has_param(schema: &serde_json::Value, key: &str) -> bool {
    schema.get("properties").and_then(|p| p.get(key)).is_some()
}

/// The groups of `combos` for images of `width × height`. A combination that cannot be built
/// is an error, or with `skip_unavailable` listed in the returned skips.
pub fn build_groups(
    combos: &[Combo],
    spec: &EvalSpec,
    registry: &Registry,
    ctx: &BuildContext,
    (width, height): (usize, usize),
    skip_unavailable: bool,
) -> Result<(Vec<Group>, Skipped), KpEvalError> {
    let mut groups: Vec<Group> = Vec::new();
    let mut skipped = Skipped::new();
    let mut fail = |combo: &Combo, stage: &str, e: CoreError| {
        if skip_unavailable {
            skipped.push((combo.name.clone(), e.to_string()));
            Ok(())
        } else {
            Err(KpEvalError::stage(&combo.name, stage, e))
        }
    };
    for combo in combos {
        let Some(det_factory) = registry.detectors.get(&combo.detector) else {
            fail(
                combo,
                "detector",
                CoreError::Config(ConfigError::Invalid {
                    origin: "registry".into(),
                    path: "kind".into(),
                    message: format!("no detector `{}`", combo.detector),
                }),
            )?;
            continue;
        };
        let wants_own = combo.own_descriptor();
        let gi = match groups
            .iter()
            .position(|g| g.detector_kind == combo.detector)
        {
            Some(i) => i,
            None => {
                let mut params = spec.params_for(&combo.detector, width, height);
                // One detector serves the robustness tests (detect only) and, for an own
                // combination, the detect-and-compute pass.
                if has_param(&det_factory.schema(), "describe") {
                    params.insert("describe".into(), true.into());
                }
                match build(det_factory, &params, &combo.detector, ctx) {
                    Ok(detector) => {
                        groups.push(Group {
                            detector_kind: combo.detector.clone(),
                            detector_name: combo.detector_name(),
                            detector,
                            combos: Vec::new(),
                            definitions: definitions(&combo.detector, spec.preset),
                        });
                        groups.len() - 1
                    }
                    Err(e) => {
                        fail(combo, "detector", e)?;
                        continue;
                    }
                }
            }
        };
        let describer = if wants_own {
            Describer::OwnPass
        } else {
            let Some(f) = registry.descriptors.get(&combo.descriptor) else {
                continue;
            };
            let params = spec.params_for(&combo.descriptor, width, height);
            match build(f, &params, &combo.descriptor, ctx) {
                Ok(d) => Describer::Separate(d),
                Err(e) => {
                    fail(combo, "descriptor", e)?;
                    continue;
                }
            }
        };
        groups[gi].combos.push((combo.clone(), describer));
    }
    groups.retain(|g| !g.combos.is_empty());
    Ok((groups, skipped))
}
