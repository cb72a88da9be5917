//! The TOML config: nine sections, each stage choosing a backend with `kind = "..."`.
//!
//! A config is read as a [`RawConfig`] (text plus `--set` overrides), then resolved against a
//! [`crate::Registry`] into a [`PipelineConfig`] in which every backend's parameters are
//! validated and every default is filled in.

mod output;
mod plugins;
mod raw;
mod render;
mod resolve;
mod trust;
mod typed;

pub use output::{OnBadFrame, OnDegenerate, OutputConfig};
pub use plugins::PluginsConfig;
pub use raw::{RawConfig, StageTable};
pub use render::{allowed_values, render_resolved, resolve_ref, unset_keys};
pub use trust::{
    check as check_trust, named_runtimes, refuse as refuse_untrusted, NamedLibrary, Trust,
    OPT_IN as TRUST_OPT_IN,
};
pub use typed::{
    ConfigBuilder, DescriptorParams, DetectorParams, DownsamplerParams, ImageParams,
    RegistrarParams, SourceParams, StageParams,
};

use std::path::PathBuf;

/// The sections of a config file, in pipeline order (`[plugins]` first: it says where
/// `kind = "plugin:NAME"` backends are found).
pub const SECTIONS: [&str; 11] = [
    "plugins",
    "source",
    "image",
    "detector",
    "descriptor",
    "downsampler",
    "registrar",
    "output",
    "ros2",
    "map",
    "localise",
];

/// The stage sections and the backend each uses when the file does not say.
pub const STAGE_DEFAULT_KINDS: [(&str, &str); 6] = [
    ("source", "sim"),
    ("image", "none"),
    ("detector", "none"),
    ("descriptor", "none"),
    ("downsampler", "passthrough"),
    ("registrar", "kiss-icp"),
];

/// The backend section `section` uses when the file does not say (`none` for a section
/// without one).
pub fn default_kind(section: &str) -> &'static str {
    STAGE_DEFAULT_KINDS
        .iter()
        .find(|(s, _)| *s == section)
        .map_or("none", |(_, k)| *k)
}

/// Stages whose section may hold per-image overrides, `[detector.by_image.<image>]`.
pub const PER_IMAGE_STAGES: [&str; 2] = ["detector", "descriptor"];

/// The key of the per-image override tables inside a [`PER_IMAGE_STAGES`] section.
pub const BY_IMAGE_KEY: &str = "by_image";

/// One stage: the backend name and its resolved parameters (defaults filled in).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StageConfig {
    pub kind: String,
    pub params: toml::Table,
    /// Per-image overrides (detector and descriptor only): the stage used for the image of
    /// that name (`signal`, `range`, `signal+range`, …) instead of this one.
    pub by_image: std::collections::BTreeMap<String, StageConfig>,
}

impl StageConfig {
    /// True for the `none` backend (stage absent).
    pub fn is_none(&self) -> bool {
        self.kind == "none"
    }
}

/// A fully resolved config.
#[derive(Debug, Clone, PartialEq)]
pub struct PipelineConfig {
    /// Where the config came from (file path or `built-in`), for messages.
    pub origin: String,
    /// Directory relative paths in the config are resolved against.
    pub base_dir: PathBuf,
    pub source: StageConfig,
    pub image: StageConfig,
    pub detector: StageConfig,
    pub descriptor: StageConfig,
    pub downsampler: StageConfig,
    pub registrar: StageConfig,
    pub output: OutputConfig,
    pub plugins: PluginsConfig,
    /// `[ros2]`: the settings of `keylo ros2` (crate `keylo-ros2` validates them; every other
    /// command carries the table through unread, so one config serves a node and a replay).
    pub ros2: toml::Table,
    /// `[map]`: the settings of the global map a run saves (`--map-out`; crate `keylo-map`
    /// validates them; runs that save no map carry the table through unread).
    pub map: toml::Table,
    /// `[localise]`: the settings of `keylo localise` (crate `keylo-map` validates them;
    /// other commands carry the table through unread).
    pub localise: toml::Table,
    /// Whether the stages may load libraries the config names (not in the file: set by the
    /// caller that checked the config under it; default [`Trust::Installed`]).
    pub trust: Trust,
}

impl PipelineConfig {
    /// The stage sections with their names, in pipeline order.
    pub fn stages(&self) -> [(&'static str, &StageConfig); 6] {
        [
            ("source", &self.source),
            ("image", &self.image),
            ("detector", &self.detector),
            ("descriptor", &self.descriptor),
            ("downsampler", &self.downsampler),
            ("registrar", &self.registrar),
        ]
    }
}
