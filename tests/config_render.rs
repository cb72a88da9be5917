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
