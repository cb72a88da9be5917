//! Configs written in code: a backend's typed parameter struct (`KissIcpConfig { .. }`) names
//! its `kind` through [`StageParams`], and a [`ConfigBuilder`] assembles the stages into the
//! same [`RawConfig`] a TOML file gives, resolved by the same registry (so validation, defaults
//! and error messages are the file's).
//!
//! ```
//! use keylo_core::config::{ConfigBuilder, RegistrarParams, StageParams};
//! use keylo_core::Registry;
//!
//! #[derive(serde::Serialize)]
//! struct Mine { gain: f64 }
//! impl StageParams for Mine { const KIND: &'static str = "mine"; }
//! impl RegistrarParams for Mine {}
//!
//! let raw = ConfigBuilder::new().registrar(&Mine { gain: 2.0 }).raw().unwrap();
//! assert_eq!(raw.table["registrar"]["kind"].as_str(), Some("mine"));
//! assert_eq!(raw.table["registrar"]["gain"].as_float(), Some(2.0));
//! // An empty registry knows no backend: resolving names the first unknown kind.
//! let err = ConfigBuilder::new()
//!     .registrar(&Mine { gain: 2.0 })
//!     .resolve(&Registry::default())
//!     .unwrap_err();
//! assert!(err.to_string().contains("is not a known"), "{err}");
//! ```

use std::path::PathBuf;

use serde::Serialize;

use super::{PipelineConfig, RawConfig, BY_IMAGE_KEY};
use crate::{ConfigError, Registry};

/// The typed parameters of one backend: serialised, they are the table of
/// `[section] kind = KIND`.
pub trait StageParams: Serialize {
    /// The backend's `kind` name.
    const KIND: &'static str;
}

/// Parameters of a `[registrar]` backend.
pub trait RegistrarParams: StageParams {}
/// Parameters of a `[downsampler]` backend.
pub trait DownsamplerParams: StageParams {}
/// Parameters of an `[image]` builder.
pub trait ImageParams: StageParams {}
/// Parameters of a `[detector]` backend.
pub trait DetectorParams: StageParams {}
/// Parameters of a `[descriptor]` backend.
pub trait DescriptorParams: StageParams {}
/// Parameters of a `[source]` backend.
pub trait SourceParams: StageParams {}

/// Assembles a config from typed parameters; a stage not set takes its default backend, as in
/// a file that leaves its section out. The setters chain; the first error (parameters that
/// do not serialise to a table, a bad `set`) is reported by [`ConfigBuilder::raw`] and
/// [`ConfigBuilder::resolve`].
#[derive(Debug)]
pub struct ConfigBuilder {
    raw: RawConfig,
    error: Option<ConfigError>,
}

impl Default for ConfigBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl ConfigBuilder {
    /// An empty config (every stage its default).
    pub fn new() -> Self {
        Self {
            raw: RawConfig {
                origin: "config built in code".into(),
                ..RawConfig::builtin()
            },
            error: None,
        }
    }

    /// Starts from a parsed config (a file or TOML text) whose sections the setters replace.
    pub fn from_raw(raw: RawConfig) -> Self {
        Self { raw, error: None }
    }

    /// Directory relative paths (models, plugins) are resolved against.
    pub fn base_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.raw.base_dir = dir.into();
        self
    }

    /// `[source]`.
    pub fn source<P: SourceParams>(self, params: &P) -> Self {
        self.section("source", params)
    }

    /// `[image]`.
    pub fn image<P: ImageParams>(self, params: &P) -> Self {
        self.section("image", params)
    }

    /// `[detector]`.
    pub fn detector<P: DetectorParams>(self, params: &P) -> Self {
        self.section("detector", params)
    }

    /// `[detector.by_image.<image>]`: the detector of one image (`signal`, `range`, …).
    pub fn detector_for<P: DetectorParams>(self, image: &str, params: &P) -> Self {
        self.by_image("detector", image, params)
    }

    /// `[descriptor]`.
    pub fn descriptor<P: DescriptorParams>(self, params: &P) -> Self {
        self.section("descriptor", params)
    }

    /// `[descriptor.by_image.<image>]`.
    pub fn descriptor_for<P: DescriptorParams>(self, image: &str, params: &P) -> Self {
        self.by_image("descriptor", image, params)
    }

    /// `[downsampler]`.
    pub fn downsampler<P: DownsamplerParams>(self, params: &P) -> Self {
        self.section("downsampler", params)
    }

    /// `[registrar]`.
    pub fn registrar<P: RegistrarParams>(self, params: &P) -> Self {
        self.section("registrar", params)
    }

    /// Sets any key as `--set` does (`registrar.max_range=50`), e.g. for a plugin's kind.
    pub fn set(self, text: &str) -> Self {
        self.record(|b| b.raw.set(text))
    }

    /// The config as a file would give it.
    pub fn raw(self) -> Result<RawConfig, ConfigError> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.raw),
        }
    }

    /// Validates every stage against `registry` and fills defaults.
    pub fn resolve(self, registry: &Registry) -> Result<PipelineConfig, ConfigError> {
        registry.resolve(&self.raw()?)
    }

    /// Records the first error of a setter.
    fn record(mut self, step: impl FnOnce(&mut Self) -> Result<(), ConfigError>) -> Self {
        if self.error.is_none() {
            if let Err(e) = step(&mut self) {
                self.error = Some(e);
            }
        }
        self
    }

    /// Replaces `[section]` by `params` (keeping its per-image overrides).
    fn section<P: StageParams>(self, section: &str, params: &P) -> Self {
        self.record(|b| b.set_section(section, params))
    }

    fn set_section<P: StageParams>(
        &mut self,
        section: &str,
        params: &P,
    ) -> Result<(), ConfigError> {
        let mut table = self.table_of(section, params)?;
        let by_image = self
            .raw
            .table
            .get(section)
            .and_then(|s| s.get(BY_IMAGE_KEY))
            .cloned();
        if let Some(by_image) = by_image {
            table.insert(BY_IMAGE_KEY.into(), by_image);
        }
        self.raw.table.insert(section.into(), table.into());
        Ok(())
    }

    fn by_image<P: StageParams>(self, section: &str, image: &str, params: &P) -> Self {
        self.record(|b| b.set_by_image(section, image, params))
    }

    fn set_by_image<P: StageParams>(
        &mut self,
        section: &str,
        image: &str,
        params: &P,
    ) -> Result<(), ConfigError> {
        let table = self.table_of(&format!("{section}.{BY_IMAGE_KEY}.{image}"), params)?;
        let stage = self
            .raw
            .table
            .entry(section)
            .or_insert_with(|| toml::Table::new().into());
        let overrides = stage
            .as_table_mut()
            .ok_or_else(|| self_invalid(section, "is not a table"))?
            .entry(BY_IMAGE_KEY)
            .or_insert_with(|| toml::Table::new().into())
            .as_table_mut()
            .ok_or_else(|| self_invalid(section, "`by_image` is not a table"))?;
        overrides.insert(image.into(), table.into());
        Ok(())
    }

    /// `params` as a stage table with its `kind`.
    fn table_of<P: StageParams>(&self, path: &str, params: &P) -> Result<toml::Table, ConfigError> {
        let mut table = toml::Table::try_from(params).map_err(|e| ConfigError::Invalid {
            origin: self.raw.origin.clone(),
            path: path.into(),
            message: format!("parameters of `{}` are not a TOML table: {e}", P::KIND),
        })?;
        table.insert("kind".into(), P::KIND.into());
        Ok(table)
    }
}

/// Implements [`StageParams`] (with the kind name) and the given stage traits for a
/// parameter struct: `stage_params!(KissIcpConfig => "kiss-icp" as RegistrarParams);`.
#[macro_export]
macro_rules! stage_params {
    ($ty:ty => $kind:literal as $($stage:ident),+) => {
        impl $crate::config::StageParams for $ty {
            const KIND: &'static str = $kind;
        }
        $(impl $crate::config::$stage for $ty {})+
    };
}

fn self_invalid(section: &str, message: &str) -> ConfigError {
    ConfigError::Invalid {
        origin: "config built in code".into(),
        path: section.into(),
        message: message.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Det {
        n: u32,
    }
    impl StageParams for Det {
        const KIND: &'static str = "det";
    }
    impl DetectorParams for Det {}

    #[test]
    fn per_image_overrides_survive_a_later_section() {
        let raw = ConfigBuilder::new()
            .detector_for("range", &Det { n: 5 })
            .detector(&Det { n: 7 })
            .raw()
            .unwrap();
        let det = &raw.table["detector"];
        assert_eq!(det["n"].as_integer(), Some(7));
        assert_eq!(det["by_image"]["range"]["n"].as_integer(), Some(5));
        assert_eq!(det["by_image"]["range"]["kind"].as_str(), Some("det"));
    }

    #[test]
    fn set_reaches_any_key() {
        let raw = ConfigBuilder::new()
            .set("registrar.max_range=12.5")
            .raw()
            .unwrap();
        assert_eq!(raw.table["registrar"]["max_range"].as_float(), Some(12.5));
    }

    #[test]
    fn the_first_error_is_kept() {
        let err = ConfigBuilder::new()
            .set("no equals sign")
            .set("registrar.max_range=1")
            .raw()
            .unwrap_err();
        assert!(err.to_string().contains("no equals sign"), "{err}");
    }
}
