//! `keylo compare --same-budget`: a keypoint configuration's same-budget baselines — its
//! keypoint windows replaced by a `random` and by a `voxel-budget` sample of as many points per
//! frame as the windows select (the same windows, mapping and pixel rule count the budget).

use keylo::config::StageConfig;

/// One way to run a configuration: as it is, or as one of its baselines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Flavour {
    /// Appended to the configuration's name (`""` for the configuration itself).
    pub suffix: String,
    /// `--set` strings that make the baseline, before the grid point's.
    pub sets: Vec<String>,
}

/// The downsamplers that sample a keypoint configuration's budget.
const BASELINES: [&str; 2] = ["random", "voxel-budget"];

/// The keys of the keypoint windows that count the budget, carried over to the baseline.
const BUDGET_KEYS: [&str; 3] = ["windows", "mapping", "pixel_points"];

/// The configuration itself and, when its downsampler takes keypoint windows, one baseline
/// per [`BASELINES`] entry counted with the same windows.
pub fn flavours(downsampler: &StageConfig) -> Vec<Flavour> {
    let mut out = vec![Flavour::default()];
    if downsampler.kind != "keypoint-neighbourhood" {
        return out;
    }
    for kind in BASELINES {
        let mut sets = vec![
            format!("downsampler.kind={kind}"),
            "downsampler.points=0".to_string(),
        ];
        for key in BUDGET_KEYS {
            if let Some(v) = downsampler.params.get(key) {
                sets.push(format!("downsampler.{key}={v}"));
            }
        }
        out.push(Flavour {
            suffix: format!(" +{kind}"),
            sets,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stage(kind: &str, params: &str) -> StageConfig {
        StageConfig {
            kind: kind.into(),
            params: params.parse().unwrap(),
            ..StageConfig::default()
        }
    }

    #[test]
    fn keypoint_configs_get_two_baselines_with_their_windows() {
        let f = flavours(&stage(
            "keypoint-neighbourhood",
            "windows = \"5_5\"\nmapping = \"exact\"\nmin_points = 50",
        ));
        assert_eq!(f.len(), 3);
        assert_eq!(f[0], Flavour::default());
        assert_eq!(f[1].suffix, " +random");
        assert_eq!(
            f[1].sets,
            [
                "downsampler.kind=random",
                "downsampler.points=0",
                "downsampler.windows=\"5_5\"",
                "downsampler.mapping=\"exact\"",
            ]
        );
        assert_eq!(f[2].sets[0], "downsampler.kind=voxel-budget");
        let table = flavours(&stage(
            "keypoint-neighbourhood",
            "windows = { signal = 4, range = 7 }",
        ));
        assert_eq!(
            table[1].sets[2],
            "downsampler.windows={ signal = 4, range = 7 }"
        );
    }

    #[test]
    fn other_downsamplers_run_as_they_are() {
        assert_eq!(
            flavours(&stage("passthrough", "")),
            vec![Flavour::default()]
        );
        assert_eq!(flavours(&stage("voxel", "voxel_size = 0.5")).len(), 1);
    }
}
