//! What an evaluation runs with: the image preparation, the metrics' parameters and every
//! detector/descriptor's parameters (a preset plus `[params.<kind>]` overrides), read from an
//! optional TOML file.

use std::collections::BTreeMap;

use keylo_core::Channel;
use keylo_features::image::{Interpolation, Normalise, NormaliseMethod};
use serde::{Deserialize, Serialize};

use keylo_core::config::{refuse_untrusted, NamedLibrary, Trust};
use keylo_core::ConfigError;

use crate::{KpEvalError, MetricParams};

/// Starting parameters of every detector and descriptor.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// The authors' study: FAST threshold 30; BRISK threshold 30, 3 octaves; Shi-Tomasi and
    /// Harris block size 4, quality 0.01, min distance 4, k 0.04, at most rows·cols/4
    /// corners; everything else at its default.
    #[default]
    Paper,
    /// Every backend at keylo's defaults (OpenCV's for the OpenCV backends).
    Defaults,
}

/// `[image]`: how a frame channel becomes the 8-bit image that is evaluated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ImageSpec {
    /// Channel of the frames: `signal`, `range`, `reflectivity` or `near-ir` (PNG folders are
    /// taken as they are).
    pub channel: String,
    /// Width the image is resized to, pixels (0: the frame's own).
    pub width: usize,
    /// Height the image is resized to, pixels (0: the frame's own).
    pub height: usize,
    /// `nearest`, `linear`, `cubic`, `area` or `lanczos4`.
    pub interpolation: Interpolation,
    /// How the channel becomes 8-bit (also applied to 16-bit PNG images). Not set: the
    /// signal of an Ouster sensor's frames (simulated or recorded: beam model `OS…`) as
    /// Ouster's ROS driver makes its signal images (`method = "ouster-ros"`), which is how the
    /// real images of the paper's study were made; anything else the `percentile` stretch.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normalise: Option<Normalise>,
}

impl Default for ImageSpec {
    fn default() -> Self {
        Self {
            channel: "signal".into(),
            width: 1024,
            height: 64,
            interpolation: Interpolation::Linear,
            normalise: None,
        }
    }
}

impl ImageSpec {
    /// The normalisation of `channel` of frames from a sensor of beam model `model`: the
    /// one set, else the driver's for an Ouster sensor's signal, else the default stretch.
    pub fn normalise_for(&self, channel: Channel, model: &str) -> Normalise {
        if let Some(n) = &self.normalise {
            return n.clone();
        }
        let ouster = model.get(..2).is_some_and(|p| p.eq_ignore_ascii_case("os"));
        if ouster && channel == Channel::Signal {
            Normalise {
                method: NormaliseMethod::OusterRos,
                ..Normalise::default()
            }
        } else {
            Normalise::default()
        }
    }

    /// The normalisation of 16-bit PNG images (8-bit ones are taken as they are): the one
    /// set, else the default stretch.
    pub fn png_normalise(&self) -> Normalise {
        self.normalise.clone().unwrap_or_default()
    }

    /// The channel, parsed.
    pub fn channel(&self) -> Result<Channel, KpEvalError> {
        self.channel
            .parse::<Channel>()
            .map_err(|m| KpEvalError::setting("image", "image.channel", m))
    }
}

/// A whole evaluation setting (`keylo keypoints eval --config FILE`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct EvalSpec {
    /// `paper` or `defaults`.
    pub preset: Preset,
    pub image: ImageSpec,
    pub metrics: MetricParams,
    /// Parameters per backend kind (`[params.fast] threshold = 20`), over the preset's.
    #[schemars(with = "BTreeMap<String, serde_json::Value>")]
    pub params: BTreeMap<String, toml::Table>,
}

impl EvalSpec {
    /// Reads a spec from TOML text; `origin` names the file in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, KpEvalError> {
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| KpEvalError::setting(origin, "", e.message()))?;
        let spec: Self = keylo_core::registry::parse_params(&table)
            .map_err(|(key, message)| KpEvalError::setting(origin, &key, message))?;
        spec.validate(origin)?;
        Ok(spec)
    }

    /// Checks the image and metric settings.
    pub fn validate(&self, origin: &str) -> Result<(), KpEvalError> {
        self.image.channel().map_err(|e| match e {
            KpEvalError::Setting { key, message, .. } => KpEvalError::Setting {
                origin: origin.into(),
                key,
                message,
            },
            other => other,
        })?;
        if let Some(n) = &self.image.normalise {
            n.validate("image.normalise")
                .map_err(|e| KpEvalError::setting(origin, "image.normalise", e.to_string()))?;
        }
        self.metrics.validate(origin)
    }

    /// Refuses, under [`Trust::Installed`], a spec naming an ONNX Runtime library of its own
    /// (`[params.<kind>] onnxruntime`): loading it would run its code (docs/plugins.md,
    /// "Trust"). `origin` names the spec in the error.
    pub fn check_trust(&self, origin: &str, trust: Trust) -> Result<(), ConfigError> {
        let named: Vec<NamedLibrary> = self
            .params
            .iter()
            .filter_map(|(kind, params)| {
                let path = params
                    .get("onnxruntime")?
                    .as_str()
                    .filter(|p| !p.is_empty())?;
                Some(NamedLibrary {
                    key: format!("params.{kind}.onnxruntime"),
                    path: path.into(),
                })
            })
            .collect();
        refuse_untrusted(origin, trust, &named)
    }

    /// The parameter table of backend `kind` for images of `width × height`: the preset's,
    /// then `[params.<kind>]` on top.
    pub fn params_for(&self, kind: &str, width: usize, height: usize) -> toml::Table {
        let mut table = match self.preset {
            Preset::Paper => paper_params(kind, width, height),
            Preset::Defaults => toml::Table::new(),
        };
        if let Some(user) = self.params.get(kind) {
            for (k, v) in user {
                table.insert(k.clone(), v.clone());
            }
        }
        table
    }
}

/// The authors' non-default parameters (`upstream-code-notes.md`).
fn paper_params(kind: &str, width: usize, height: usize) -> toml::Table {
    let mut t = toml::Table::new();
    let mut set = |k: &str, v: toml::Value| {
        t.insert(k.into(), v);
    };
    match kind {
        "fast" => {
            set("threshold", 30.into());
            set("nonmax_suppression", true.into());
            set("detector_type", "9_16".into());
        }
        "brisk" => {
            set("thresh", 30.into());
            set("octaves", 3.into());
            set("pattern_scale", 1.0.into());
        }
        "shi-tomasi" | "harris" => {
            let corners = i64::try_from(width * height / 4).unwrap_or(i64::from(i32::MAX));
            set("max_corners", corners.min(i64::from(i32::MAX)).into());
            set("quality_level", 0.01.into());
            set("min_distance", 4.0.into());
            set("block_size", 4.into());
            set("k", 0.04.into());
        }
        _ => {}
    }
    t
}

/// The kebab-case name of an interpolation (`lanczos4`).
pub fn interpolation_name(i: Interpolation) -> String {
    serde_json::to_value(i)
        .ok()
        .and_then(|v| v.as_str().map(String::from))
        .unwrap_or_default()
}

/// An interpolation by name.
pub fn parse_interpolation(name: &str) -> Result<Interpolation, KpEvalError> {
    serde_json::from_value(serde_json::Value::String(name.trim().to_ascii_lowercase())).map_err(
        |_| {
            KpEvalError::setting(
                "sweep",
                "interpolations",
                format!("`{name}`: expected nearest, linear, cubic, area or lanczos4"),
            )
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_preset_and_overrides() {
        let spec = EvalSpec::from_toml(
            "[params.fast]\nthreshold = 20\n[image]\nwidth = 512\n",
            "eval.toml",
        )
        .unwrap();
        assert_eq!(spec.image.width, 512);
        let fast = spec.params_for("fast", 512, 64);
        assert_eq!(fast["threshold"].as_integer(), Some(20));
        assert_eq!(fast["nonmax_suppression"].as_bool(), Some(true));
        let gftt = spec.params_for("shi-tomasi", 1024, 64);
        assert_eq!(gftt["max_corners"].as_integer(), Some(16384));
        assert_eq!(gftt["block_size"].as_integer(), Some(4));
        let plain = EvalSpec {
            preset: Preset::Defaults,
            ..EvalSpec::default()
        };
        assert!(plain.params_for("shi-tomasi", 1024, 64).is_empty());
    }

    #[test]
    fn bad_settings_name_the_file_and_key() {
        let e = EvalSpec::from_toml("[metrics]\nrepeat_px = -1\n", "my.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("my.toml") && e.contains("metrics.repeat_px"),
            "{e}"
        );
        let e = EvalSpec::from_toml("[image]\nchannel = \"colour\"\n", "my.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("my.toml") && e.contains("image.channel"), "{e}");
        let e = EvalSpec::from_toml("[metrics]\nrepeat = 3\n", "my.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("my.toml") && e.contains("metrics"), "{e}");
    }

    #[test]
    fn an_ouster_sensors_signal_is_normalised_as_its_driver_does_unless_set() {
        let spec = EvalSpec::default();
        for (channel, model, want) in [
            (Channel::Signal, "OS0-128", NormaliseMethod::OusterRos),
            (Channel::Signal, "os-1-64", NormaliseMethod::OusterRos),
            (Channel::Range, "OS0-128", NormaliseMethod::Percentile),
            (Channel::Signal, "HDL-64E", NormaliseMethod::Percentile),
        ] {
            let got = spec.image.normalise_for(channel, model).method;
            assert_eq!(got, want, "{channel:?} of {model}");
        }
        assert_eq!(
            spec.image.png_normalise().method,
            NormaliseMethod::Percentile
        );
        let set = EvalSpec::from_toml("[image.normalise]\nmethod = \"equalise\"\n", "t").unwrap();
        assert_eq!(
            set.image.normalise_for(Channel::Signal, "OS0-128").method,
            NormaliseMethod::Equalise
        );
    }
}
