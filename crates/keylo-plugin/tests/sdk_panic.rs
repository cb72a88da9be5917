//! A Rust plugin that panics: the SDK catches the panic at the C boundary and keylo gets an
//! error naming the plugin, not an abort. The plugin is exported into this test binary with
//! `export_plugin!` and its table is checked by the same code that checks a loaded library.

use std::path::Path;
use std::sync::Arc;

use keylo_core::{Channel, CoreError, Detector, Image, Keypoint, Registry};
use keylo_plugin::host::{register_plugin, Plugin};
use keylo_plugin::FromConfig;
use serde::Deserialize;

#[derive(Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct Params {
    panic_in_configure: bool,
}

struct Panicky;

impl FromConfig for Panicky {
    type Params = Params;
    fn from_params(p: Params) -> Result<Self, String> {
        if p.panic_in_configure {
            panic!("configure exploded");
        }
        Ok(Self)
    }
}

impl Detector for Panicky {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        let v: Vec<usize> = Vec::new();
        // An out-of-bounds index: a genuine panic, not a `panic!` call.
        let _ = v[image.width];
        Ok(Vec::new())
    }
}

keylo_plugin::export_plugin! {
    name: "panicky",
    version: "9.9.9",
    detector: Panicky => "panics on every image",
}

fn registry() -> (Registry, Arc<Plugin>) {
    // SAFETY: the table comes from this binary's own `keylo_plugin_entry`.
    let plugin = unsafe { Plugin::from_info(keylo_plugin_entry(), Path::new("(this test)")) }
        .map(Arc::new)
        .unwrap();
    let mut registry = Registry::default();
    register_plugin(&mut registry, &plugin);
    (registry, plugin)
}

#[test]
fn exported_table_is_checked_and_registered() {
    let (registry, plugin) = registry();
    assert_eq!(
        (plugin.name.as_str(), plugin.version.as_str()),
        ("panicky", "9.9.9")
    );
    assert_eq!(registry.detectors.kinds(), ["plugin:panicky"]);
    assert!(registry.descriptors.kinds().is_empty());
}

#[test]
fn a_panic_in_detect_becomes_an_error_naming_the_plugin() {
    let (registry, _) = registry();
    let factory = registry.detectors.get("plugin:panicky").unwrap();
    let mut det = factory
        .build(&toml::Table::new(), &Default::default())
        .unwrap();
    let image = Image::new_gray(8, 4, Channel::Signal);
    let e = det
        .detect(&image)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("plugin `panicky`"), "{e}");
    assert!(e.contains("detect panicked (code 4)"), "{e}");
    assert!(e.contains("index out of bounds"), "{e}");
    // The instance survives and keeps answering with errors.
    assert!(det.detect(&image).is_err());
}

/// The error of building the `panicky` detector with `params` (empty when it builds).
fn build_error(params: &str) -> String {
    let (registry, _) = registry();
    let factory = registry.detectors.get("plugin:panicky").unwrap();
    let params: toml::Table = params.parse().unwrap();
    factory
        .build(&params, &Default::default())
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
}

#[test]
fn a_panic_in_configure_becomes_an_error() {
    let e = build_error("panic_in_configure = true");
    assert!(
        e.contains("configure panicked") && e.contains("configure exploded"),
        "{e}"
    );
}

#[test]
fn unknown_parameters_are_rejected_by_the_sdk() {
    let e = build_error("nope = 1");
    assert!(
        e.contains("configuration rejected") && e.contains("nope"),
        "{e}"
    );
}
