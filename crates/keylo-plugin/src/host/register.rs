//! Plugin kinds as registry factories, and loading the plugins a config names.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

use keylo_core::config::{check_trust, NamedLibrary, RawConfig, Trust};
use keylo_core::registry::{BuildContext, Factory};
use keylo_core::{CoreError, Descriptor, Detector, Downsampler, Registrar, Registry};

use super::instance::{Instance, RegistrarInstance};
use super::library::{Kind, Plugin, Stage};
use super::search::{SearchPath, CONFIG_DIRS};
use crate::PluginError;

/// The prefix of plugin kinds: `kind = "plugin:NAME"`.
pub const KIND_PREFIX: &str = "plugin:";

/// One plugin kind as the factory of a stage trait `T`.
struct PluginFactory<T: ?Sized> {
    plugin: Arc<Plugin>,
    kind: Kind,
    summary: String,
    wrap: fn(Instance) -> Box<T>,
}

impl<T: ?Sized> Factory<T> for PluginFactory<T> {
    fn summary(&self) -> &str {
        &self.summary
    }

    fn schema(&self) -> serde_json::Value {
        serde_json::json!({
            "type": "object",
            "description": format!(
                "parameters passed to plugin `{}` as TOML; it checks them when the stage is built",
                self.plugin.name
            ),
        })
    }

    fn resolve(&self, params: &toml::Table) -> Result<toml::Table, (String, String)> {
        Ok(params.clone())
    }

    fn build(&self, params: &toml::Table, _ctx: &BuildContext) -> Result<Box<T>, CoreError> {
        let inst = Instance::new(self.plugin.clone(), self.kind.clone(), params)?;
        Ok((self.wrap)(inst))
    }
}

fn factory<T: ?Sized>(
    plugin: &Arc<Plugin>,
    kind: &Kind,
    wrap: fn(Instance) -> Box<T>,
) -> Box<PluginFactory<T>> {
    let summary = format!(
        "{} (plugin {} {}, {})",
        kind.summary,
        plugin.name,
        plugin.version,
        plugin.path.display()
    );
    Box::new(PluginFactory {
        plugin: plugin.clone(),
        kind: kind.clone(),
        summary,
        wrap,
    })
}

/// Registers every kind of `plugin` as `plugin:NAME` in its stage.
pub fn register_plugin(registry: &mut Registry, plugin: &Arc<Plugin>) {
    let name = format!("{KIND_PREFIX}{}", plugin.name);
    for kind in &plugin.kinds {
        match kind.stage {
            Stage::Detector => registry.detectors.add_factory(
                &name,
                factory(plugin, kind, |i| Box::new(i) as Box<dyn Detector>),
            ),
            Stage::Descriptor => registry.descriptors.add_factory(
                &name,
                factory(plugin, kind, |i| Box::new(i) as Box<dyn Descriptor>),
            ),
            Stage::Downsampler => registry.downsamplers.add_factory(
                &name,
                factory(plugin, kind, |i| Box::new(i) as Box<dyn Downsampler>),
            ),
            Stage::Registrar => registry.registrars.add_factory(
                &name,
                factory(plugin, kind, |i| {
                    Box::new(RegistrarInstance::from(i)) as Box<dyn Registrar>
                }),
            ),
        }
    }
}

/// Every `(section, plugin name)` a raw config names with `kind = "plugin:NAME"`, per-image
/// overrides included.
pub fn referenced(raw: &RawConfig) -> Vec<(String, String)> {
    raw.stage_tables()
        .into_iter()
        .filter_map(|t| {
            let name = t
                .table
                .get("kind")
                .and_then(toml::Value::as_str)
                .and_then(|k| k.strip_prefix(KIND_PREFIX))?;
            Some((t.section.to_string(), name.to_string()))
        })
        .collect()
}

/// Whether `name` is a plugin name and nothing else: ASCII letters, digits, `-` and `_`.
pub fn is_plain_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_')
}

/// The search path of a raw config: its `[plugins] dirs`, `KEYLO_PLUGIN_PATH`, the default.
pub fn search_path(raw: &RawConfig) -> Result<SearchPath, PluginError> {
    let plugins = raw.plugins()?;
    Ok(SearchPath::new(&plugins.dir_paths(&raw.base_dir)))
}

/// Finds, loads and registers every plugin `raw` names, checking that each offers the stage
/// that names it. Returns the plugins loaded.
///
/// Under [`Trust::Installed`] a config whose plugins would come from its own `[plugins] dirs`,
/// or that names an `onnxruntime` library, is refused before anything is loaded
/// (see [`keylo_core::config::check_trust`]). Each library loaded is logged with its path.
pub fn load_for_config(
    registry: &mut Registry,
    raw: &RawConfig,
    trust: Trust,
) -> Result<Vec<Arc<Plugin>>, PluginError> {
    let wanted = referenced(raw);
    // A name is a file name's stem: a path in it would reach outside every folder searched.
    if let Some((section, name)) = wanted.iter().find(|(_, n)| !is_plain_name(n)) {
        return Err(PluginError::BadName {
            section: section.clone(),
            name: name.clone(),
        });
    }
    let search = search_path(raw)?;
    // Every file first: nothing is loaded unless all may be.
    let mut files: BTreeMap<String, PathBuf> = BTreeMap::new();
    let mut named = Vec::new();
    for (_, name) in &wanted {
        if files.contains_key(name) {
            continue;
        }
        let (path, from) = search.find_with_origin(name)?;
        if from == CONFIG_DIRS {
            named.push(NamedLibrary {
                key: CONFIG_DIRS.into(),
                path: path.clone(),
            });
        }
        files.insert(name.clone(), path);
    }
    check_trust(raw, trust, &named)?;
    let mut loaded: BTreeMap<String, Arc<Plugin>> = BTreeMap::new();
    for (section, name) in wanted {
        let plugin = match loaded.get(&name) {
            Some(p) => p.clone(),
            None => {
                let path = files[&name].clone();
                let plugin = Plugin::open(&path)?;
                if plugin.name != name {
                    return Err(PluginError::NameMismatch {
                        path,
                        expected: name,
                        found: plugin.name.clone(),
                    });
                }
                register_plugin(registry, &plugin);
                loaded.insert(name.clone(), plugin.clone());
                plugin
            }
        };
        if !plugin.kinds.iter().any(|k| k.stage.section() == section) {
            return Err(PluginError::WrongStage {
                name,
                path: plugin.path.clone(),
                section,
                offered: plugin.offered(),
            });
        }
    }
    Ok(loaded.into_values().collect())
}
