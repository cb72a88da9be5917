//! [`FrontendBuilder`]: a [`crate::Frontend`] from typed configs, stage instances of your own,
//! or both.

use std::path::PathBuf;

use keylo_core::config::{
    ConfigBuilder, DescriptorParams, DetectorParams, DownsamplerParams, ImageParams, RawConfig,
    RegistrarParams, Trust,
};
use keylo_core::{Downsampler, Registrar, Registry};
use keylo_io::cloud::ProjectionConfig;

use super::{Error, Frontend};

/// Assembles a [`Frontend`]: each stage from its typed parameters (`KissIcpConfig { .. }`), a
/// stage not set taking its default backend (passthrough, KISS-ICP); or a registrar or
/// downsampler instance of your own. Errors surface in [`FrontendBuilder::build`].
///
/// ```
/// use keylo::registration::{KissIcpConfig, NdtConfig};
/// let kiss = keylo::Frontend::builder()
///     .registrar(&KissIcpConfig { max_range: 50.0, ..Default::default() })
///     .build()
///     .unwrap();
/// assert_eq!(kiss.frames(), 0);
/// // The same checks as a config file: a bad value names its key.
/// let err = keylo::Frontend::builder()
///     .registrar(&NdtConfig { resolution: -1.0, ..Default::default() })
///     .build()
///     .err()
///     .unwrap();
/// assert!(err.to_string().contains("resolution"), "{err}");
/// ```
pub struct FrontendBuilder {
    config: ConfigBuilder,
    registry: Option<Registry>,
    trust: Trust,
    projection: ProjectionConfig,
    registrar: Option<Box<dyn Registrar>>,
    downsampler: Option<Box<dyn Downsampler>>,
}

impl Default for FrontendBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl FrontendBuilder {
    /// Every stage at its default.
    pub fn new() -> Self {
        Self::from_raw(RawConfig::builtin())
    }

    /// Starts from a parsed config whose sections the setters replace.
    pub fn from_raw(raw: RawConfig) -> Self {
        Self {
            config: ConfigBuilder::from_raw(raw),
            registry: None,
            trust: Trust::Installed,
            projection: ProjectionConfig::default(),
            registrar: None,
            downsampler: None,
        }
    }

    /// The registry kinds are looked up in (default: [`crate::registry`]); add your own
    /// backends to it to name them by kind.
    pub fn registry(mut self, registry: Registry) -> Self {
        self.registry = Some(registry);
        self
    }

    /// Whether the libraries the config names itself (`[plugins] dirs`, `onnxruntime`) may be
    /// loaded (default [`Trust::Installed`]: such a config is refused; docs/plugins.md).
    pub fn trust(mut self, trust: Trust) -> Self {
        self.trust = trust;
        self
    }

    /// How pushed point clouds become frames (`[source.projection]`; default: the generic
    /// 64×1024 grid with rows from elevation).
    pub fn projection(mut self, projection: ProjectionConfig) -> Self {
        self.projection = projection;
        self
    }

    /// Directory relative paths (models, plugins) are resolved against.
    pub fn base_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.config = self.config.base_dir(dir);
        self
    }

    /// `[image]`.
    pub fn image<P: ImageParams>(mut self, params: &P) -> Self {
        self.config = self.config.image(params);
        self
    }

    /// `[detector]`.
    pub fn detector<P: DetectorParams>(mut self, params: &P) -> Self {
        self.config = self.config.detector(params);
        self
    }

    /// `[detector.by_image.<image>]`.
    pub fn detector_for<P: DetectorParams>(mut self, image: &str, params: &P) -> Self {
        self.config = self.config.detector_for(image, params);
        self
    }

    /// `[descriptor]`.
    pub fn descriptor<P: DescriptorParams>(mut self, params: &P) -> Self {
        self.config = self.config.descriptor(params);
        self
    }

    /// `[descriptor.by_image.<image>]`.
    pub fn descriptor_for<P: DescriptorParams>(mut self, image: &str, params: &P) -> Self {
        self.config = self.config.descriptor_for(image, params);
        self
    }

    /// `[downsampler]`.
    pub fn downsampler<P: DownsamplerParams>(mut self, params: &P) -> Self {
        self.config = self.config.downsampler(params);
        self
    }

    /// `[registrar]`.
    pub fn registrar<P: RegistrarParams>(mut self, params: &P) -> Self {
        self.config = self.config.registrar(params);
        self
    }

    /// Any key, as `--set` does (`registrar.max_range=50`).
    pub fn set(mut self, text: &str) -> Self {
        self.config = self.config.set(text);
        self
    }

    /// A registrar of your own instead of the configured one.
    pub fn registrar_instance(mut self, registrar: Box<dyn Registrar>) -> Self {
        self.registrar = Some(registrar);
        self
    }

    /// A downsampler of your own instead of the configured one.
    pub fn downsampler_instance(mut self, downsampler: Box<dyn Downsampler>) -> Self {
        self.downsampler = Some(downsampler);
        self
    }

    /// Resolves the config, builds the stages and puts in the instances given.
    pub fn build(self) -> Result<Frontend, Error> {
        let raw = self.config.raw()?;
        let registry = self.registry.unwrap_or_else(crate::registry);
        let mut odometry = super::odometry_of(&raw, registry, self.trust)?;
        let own_registrar = self.registrar.is_some();
        if let Some(r) = self.registrar {
            odometry.registrar = r;
        }
        if let Some(d) = self.downsampler {
            odometry.downsampler = d;
        }
        let mut frontend = Frontend::with_odometry(odometry, &self.projection)?;
        if !own_registrar {
            frontend.set_noise_model(super::noise_of(&raw));
        }
        Ok(frontend)
    }
}
