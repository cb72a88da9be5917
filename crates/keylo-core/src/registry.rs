//! Maps `kind = "..."` names to backend constructors, per stage.
//!
//! Built-in crates add their backends with [`Backends::add`]; the plugin loader will add plugin
//! kinds the same way. A backend's parameters are a serde struct with `Default`, so one
//! definition gives validation, defaults, `keylo config show` and the config reference.

use std::collections::BTreeMap;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::stages::{Descriptor, Detector, Downsampler, ImageBuilder, ImageSource, Registrar};
use crate::CoreError;

/// What a constructor may need besides its parameters.
#[derive(Debug, Clone, Default)]
pub struct BuildContext {
    /// Directory that relative paths in the config are resolved against.
    pub base_dir: PathBuf,
    /// Whether a stage may load a library its parameters name (`onnxruntime`): only under
    /// [`crate::config::Trust::Config`] (docs/plugins.md, "Trust").
    pub trust: crate::config::Trust,
}

impl BuildContext {
    /// Refuses, unless trusted, a library path `value` named by parameter `key` of a stage.
    pub fn check_library(&self, key: &str, value: &str) -> Result<(), crate::ConfigError> {
        if value.is_empty() {
            return Ok(());
        }
        let named = crate::config::NamedLibrary {
            key: key.into(),
            path: value.into(),
        };
        crate::config::refuse_untrusted("the stage's parameters", self.trust, &[named])
    }

    /// `path` resolved against the config directory.
    pub fn resolve_path(&self, path: &str) -> PathBuf {
        let p = Path::new(path);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base_dir.join(p)
        }
    }
}

/// A backend constructor with its parameter schema.
pub trait Factory<T: ?Sized>: Send + Sync {
    /// One line saying what the backend does.
    fn summary(&self) -> &str;
    /// JSON schema of the parameters (descriptions are the fields' doc comments).
    fn schema(&self) -> serde_json::Value;
    /// Validates `params` and returns them with every default filled in.
    /// The error is `(key path inside the section, message)`.
    fn resolve(&self, params: &toml::Table) -> Result<toml::Table, (String, String)>;
    /// Builds the backend from resolved parameters.
    fn build(&self, params: &toml::Table, ctx: &BuildContext) -> Result<Box<T>, CoreError>;
}

type BuildFn<C, T> = fn(C, &BuildContext) -> Result<Box<T>, CoreError>;

/// A [`Factory`] for a typed parameter struct `C`.
pub struct Typed<C, T: ?Sized> {
    summary: &'static str,
    build: BuildFn<C, T>,
    _params: PhantomData<fn() -> C>,
}

impl<C, T> Factory<T> for Typed<C, T>
where
    C: DeserializeOwned + Serialize + schemars::JsonSchema + Default,
    T: ?Sized,
{
    fn summary(&self) -> &str {
        self.summary
    }

    fn schema(&self) -> serde_json::Value {
        schemars::schema_for!(C).to_value()
    }

    fn resolve(&self, params: &toml::Table) -> Result<toml::Table, (String, String)> {
        let typed = parse_params::<C>(params)?;
        match toml::Table::try_from(&typed) {
            Ok(t) => Ok(t),
            Err(e) => Err((String::new(), e.to_string())),
        }
    }

    fn build(&self, params: &toml::Table, ctx: &BuildContext) -> Result<Box<T>, CoreError> {
        let typed = parse_params::<C>(params).map_err(|(path, message)| {
            CoreError::Config(crate::ConfigError::Invalid {
                origin: "parameters".into(),
                path,
                message,
            })
        })?;
        (self.build)(typed, ctx)
    }
}

/// Deserialises a parameter table into `C`, reporting the failing key path.
pub fn parse_params<C: DeserializeOwned>(params: &toml::Table) -> Result<C, (String, String)> {
    let value = toml::Value::Table(params.clone());
    serde_path_to_error::deserialize::<_, C>(value).map_err(|e| {
        let path = e.path().to_string();
        let path = if path == "." { String::new() } else { path };
        // toml appends its own "in `key`" line; the path is reported separately.
        let message = e.into_inner().to_string();
        let first = message
            .lines()
            .next()
            .unwrap_or_default()
            .trim()
            .to_string();
        (path, first)
    })
}

/// The backends of one stage.
pub struct Backends<T: ?Sized> {
    map: BTreeMap<String, Box<dyn Factory<T>>>,
}

impl<T: ?Sized> Default for Backends<T> {
    fn default() -> Self {
        Self {
            map: BTreeMap::new(),
        }
    }
}

impl<T: ?Sized + 'static> Backends<T> {
    /// Registers `kind` with parameter struct `C` and constructor `build`.
    pub fn add<C>(&mut self, kind: &str, summary: &'static str, build: BuildFn<C, T>)
    where
        C: DeserializeOwned + Serialize + schemars::JsonSchema + Default + 'static,
    {
        let factory = Typed::<C, T> {
            summary,
            build,
            _params: PhantomData,
        };
        self.map.insert(kind.to_string(), Box::new(factory));
    }

    /// Registers a ready-made factory (used by plugins).
    pub fn add_factory(&mut self, kind: &str, factory: Box<dyn Factory<T>>) {
        self.map.insert(kind.to_string(), factory);
    }

    /// The factory of `kind`.
    pub fn get(&self, kind: &str) -> Option<&dyn Factory<T>> {
        self.map.get(kind).map(|b| b.as_ref())
    }

    /// Registered kind names, sorted.
    pub fn kinds(&self) -> Vec<&str> {
        self.map.keys().map(String::as_str).collect()
    }

    /// `(kind, summary)` pairs, sorted by kind.
    pub fn summaries(&self) -> Vec<(&str, &str)> {
        self.map
            .iter()
            .map(|(k, f)| (k.as_str(), f.summary()))
            .collect()
    }
}

/// A test that says whether a path holds data a source kind reads.
pub type SourceProbe = fn(&Path) -> bool;

/// Every registered backend, per stage.
#[derive(Default)]
pub struct Registry {
    pub sources: Backends<dyn ImageSource>,
    pub images: Backends<dyn ImageBuilder>,
    pub detectors: Backends<dyn Detector>,
    pub descriptors: Backends<dyn Descriptor>,
    pub downsamplers: Backends<dyn Downsampler>,
    pub registrars: Backends<dyn Registrar>,
    probes: Vec<(String, SourceProbe)>,
}

impl Registry {
    /// Registers a data-path probe for source `kind` (used by `--data` auto-detection).
    pub fn add_source_probe(&mut self, kind: &str, probe: SourceProbe) {
        self.probes.push((kind.to_string(), probe));
    }

    /// The source kind that reads `path`, if a probe recognises it.
    pub fn detect_source(&self, path: &Path) -> Option<&str> {
        self.probes
            .iter()
            .find(|(_, probe)| probe(path))
            .map(|(k, _)| k.as_str())
    }

    /// The source kind that reads the data at `path` (as `keylo run --data` picks it) and the
    /// path made absolute; an input error when the path is missing or no probe recognises it
    /// (listing the kinds that have one).
    pub fn source_for_data(&self, path: &Path) -> Result<(String, PathBuf), CoreError> {
        if !path.exists() {
            return Err(CoreError::input(path, "no such file or directory"));
        }
        let kind = self.detect_source(path).ok_or_else(|| {
            CoreError::input(
                path,
                format!(
                    "no source recognises this data (readable kinds: {})",
                    self.probed_kinds().join(", ")
                ),
            )
        })?;
        let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        Ok((kind.to_string(), absolute))
    }

    /// Source kinds that have a probe (for error messages).
    pub fn probed_kinds(&self) -> Vec<&str> {
        self.probes.iter().map(|(k, _)| k.as_str()).collect()
    }

    /// Kinds and schemas of a stage section, `None` for an unknown section.
    pub fn section_kinds(&self, section: &str) -> Option<Vec<&str>> {
        Some(match section {
            "source" => self.sources.kinds(),
            "image" => self.images.kinds(),
            "detector" => self.detectors.kinds(),
            "descriptor" => self.descriptors.kinds(),
            "downsampler" => self.downsamplers.kinds(),
            "registrar" => self.registrars.kinds(),
            _ => return None,
        })
    }

    /// Summary and parameter schema of `section.kind`.
    pub fn describe(&self, section: &str, kind: &str) -> Option<(String, serde_json::Value)> {
        fn d<T: ?Sized + 'static>(
            b: &Backends<T>,
            kind: &str,
        ) -> Option<(String, serde_json::Value)> {
            b.get(kind).map(|f| (f.summary().to_string(), f.schema()))
        }
        match section {
            "source" => d(&self.sources, kind),
            "image" => d(&self.images, kind),
            "detector" => d(&self.detectors, kind),
            "descriptor" => d(&self.descriptors, kind),
            "downsampler" => d(&self.downsamplers, kind),
            "registrar" => d(&self.registrars, kind),
            _ => None,
        }
    }

    /// Validates `section.kind`'s parameters and fills defaults.
    pub fn resolve_params(
        &self,
        section: &str,
        kind: &str,
        params: &toml::Table,
    ) -> Option<Result<toml::Table, (String, String)>> {
        fn r<T: ?Sized + 'static>(
            b: &Backends<T>,
            kind: &str,
            p: &toml::Table,
        ) -> Option<Result<toml::Table, (String, String)>> {
            b.get(kind).map(|f| f.resolve(p))
        }
        match section {
            "source" => r(&self.sources, kind, params),
            "image" => r(&self.images, kind, params),
            "detector" => r(&self.detectors, kind, params),
            "descriptor" => r(&self.descriptors, kind, params),
            "downsampler" => r(&self.downsamplers, kind, params),
            "registrar" => r(&self.registrars, kind, params),
            _ => None,
        }
    }
}
