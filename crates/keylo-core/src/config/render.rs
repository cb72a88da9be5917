use std::fmt::Write;

use serde_json::Value;

use super::{OutputConfig, PipelineConfig, PluginsConfig, StageConfig, BY_IMAGE_KEY};
use crate::Registry;

/// The resolved config as TOML, each key preceded by its documentation.
pub fn render_resolved(config: &PipelineConfig, registry: &Registry) -> String {
    let mut out = format!("# keylo config resolved from {}\n", config.origin);
    if config.plugins != PluginsConfig::default() {
        out.push_str("\n[plugins]\n");
        let schema = schemars::schema_for!(PluginsConfig).to_value();
        let mut plugins = config.plugins.clone();
        // Written out absolute: the rendered file may be read from another folder.
        plugins.dirs = plugins
            .dir_paths(&config.base_dir)
            .iter()
            .map(|p| p.display().to_string())
            .collect();
        if let Ok(table) = toml::Table::try_from(&plugins) {
            write_table(&mut out, "plugins", &table, &schema, &schema);
        }
    }
    for (section, stage) in config.stages() {
        write_stage(&mut out, registry, section, section, stage);
        for (image, sub) in &stage.by_image {
            let path = format!("{section}.{BY_IMAGE_KEY}.{image}");
            write_stage(&mut out, registry, section, &path, sub);
        }
    }
    out.push_str("\n[output]\n");
    let schema = schemars::schema_for!(OutputConfig).to_value();
    if let Ok(table) = toml::Table::try_from(&config.output) {
        write_table(&mut out, "output", &table, &schema, &schema);
    }
    if !config.ros2.is_empty() {
        // Validated and documented by `keylo ros2` (crate keylo-ros2), not by the registry.
        out.push_str("\n[ros2]\n");
        write_table(&mut out, "ros2", &config.ros2, &Value::Null, &Value::Null);
    }
    if !config.map.is_empty() {
        // Validated and documented by crate keylo-map, not by the registry.
        out.push_str("\n[map]\n");
        write_table(&mut out, "map", &config.map, &Value::Null, &Value::Null);
    }
    if !config.localise.is_empty() {
        // Validated and documented by crate keylo-map, not by the registry.
        out.push_str("\n[localise]\n");
        write_table(
            &mut out,
            "localise",
            &config.localise,
            &Value::Null,
            &Value::Null,
        );
    }
    out
}

fn write_stage(
    out: &mut String,
    registry: &Registry,
    section: &str,
    path: &str,
    stage: &StageConfig,
) {
    let _ = write!(out, "\n[{path}]\n");
    let described = registry.describe(section, &stage.kind);
    if let Some((summary, _)) = &described {
        let _ = writeln!(out, "# {summary}");
    }
    let _ = writeln!(out, "kind = {}", toml::Value::String(stage.kind.clone()));
    let schema = described.map(|(_, s)| s).unwrap_or(Value::Null);
    write_table(out, path, &stage.params, &schema, &schema);
}

fn write_table(out: &mut String, path: &str, table: &toml::Table, schema: &Value, root: &Value) {
    let props = resolve_ref(schema, root).get("properties");
    let mut nested = Vec::new();
    for (key, value) in table {
        let field = props.and_then(|p| p.get(key)).unwrap_or(&Value::Null);
        if let toml::Value::Table(sub) = value {
            nested.push((key, sub, field));
            continue;
        }
        if let Some(doc) = field.get("description").and_then(Value::as_str) {
            for line in doc.lines() {
                let _ = writeln!(out, "# {line}");
            }
        }
        let _ = writeln!(out, "{key} = {value}");
    }
    // Optional keys left unset (their default comes from another key, e.g. a sensor).
    for (key, field) in unset_keys(props, table) {
        if let Some(doc) = field.get("description").and_then(Value::as_str) {
            for line in doc.lines() {
                let _ = writeln!(out, "# {line}");
            }
        }
        let _ = writeln!(out, "# {key} = (unset)");
    }
    for (key, sub, field) in nested {
        let sub_path = format!("{path}.{key}");
        let _ = write!(out, "\n[{sub_path}]\n");
        if let Some(doc) = field.get("description").and_then(Value::as_str) {
            for line in doc.lines() {
                let _ = writeln!(out, "# {line}");
            }
        }
        write_table(out, &sub_path, sub, field, root);
    }
}

/// Follows a `$ref` (possibly behind `allOf`) of a JSON-schema node to its definition in the
/// root's `$defs`; a node without one is returned as is.
pub fn resolve_ref<'a>(schema: &'a Value, root: &'a Value) -> &'a Value {
    let reference = schema.get("$ref").or_else(|| {
        schema
            .get("allOf")
            .and_then(|a| a.get(0))
            .and_then(|s| s.get("$ref"))
    });
    match reference.and_then(Value::as_str) {
        Some(r) => r
            .strip_prefix("#/$defs/")
            .and_then(|name| root.get("$defs").and_then(|d| d.get(name)))
            .unwrap_or(schema),
        None => schema,
    }
}

/// The allowed values of an enum-typed schema field (`enum`, or `oneOf` of `const`s, possibly
/// behind a `$ref`); empty for other fields.
pub fn allowed_values(field: &Value, root: &Value) -> Vec<String> {
    let target = resolve_ref(field, root);
    let mut values: Vec<String> = Vec::new();
    if let Some(list) = target.get("enum").and_then(Value::as_array) {
        values.extend(list.iter().filter_map(Value::as_str).map(str::to_string));
    }
    if let Some(list) = target.get("oneOf").and_then(Value::as_array) {
        for v in list {
            let c = v
                .get("const")
                .or_else(|| v.get("enum").and_then(|e| e.get(0)));
            values.extend(c.and_then(Value::as_str).map(str::to_string));
        }
    }
    values
}

/// The schema's properties that `table` does not hold (optional keys left unset).
pub fn unset_keys<'a>(
    props: Option<&'a Value>,
    table: &'a toml::Table,
) -> impl Iterator<Item = (&'a String, &'a Value)> {
    props
        .and_then(Value::as_object)
        .into_iter()
        .flatten()
        .filter(move |(k, _)| !table.contains_key(k.as_str()))
}
