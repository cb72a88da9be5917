//! `--grid KEY=V1,V2,…`: parsing, aliases and the cartesian product of assignments.

use std::collections::BTreeMap;

use super::error::CompareError;

/// Short names accepted for the downsampler's window sizes (documented in `keylo compare
/// --help` and docs/results/odometry.md).
pub const ALIASES: [(&str, &str); 4] = [
    ("k_sig", "downsampler.windows.signal"),
    ("k_rng", "downsampler.windows.range"),
    ("downsampler.k_sig", "downsampler.windows.signal"),
    ("downsampler.k_rng", "downsampler.windows.range"),
];

/// Prefix of the per-image window sizes, which are merged into one `downsampler.windows`
/// table per run (the config may hold them as a preset string such as `"4_7"`).
pub const WINDOWS_PREFIX: &str = "downsampler.windows.";

/// One grid dimension: a config key and the values it takes.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The key as given (an alias stays an alias here, for labels).
    pub name: String,
    /// The config key path the values go to.
    pub key: String,
    pub values: Vec<String>,
}

/// One point of the grid: `(axis name, key, value)` for every axis.
pub type Assignment = Vec<(String, String, String)>;

/// Parses one `--grid KEY=V1,V2,…` (commas inside `[]`, `{}` or quotes do not split).
pub fn parse_axis(text: &str) -> Result<Axis, CompareError> {
    let bad = |key: &str, message: &str| CompareError::BadGrid {
        key: key.to_string(),
        message: message.to_string(),
    };
    let Some((name, list)) = text.split_once('=') else {
        return Err(bad(text, "expected KEY=V1,V2,… such as k_sig=4,5,7"));
    };
    let name = name.trim();
    if name.is_empty() || name.split('.').any(str::is_empty) {
        return Err(bad(text, "empty key in path"));
    }
    let key = ALIASES
        .iter()
        .find(|(a, _)| *a == name)
        .map_or(name, |(_, k)| k)
        .to_string();
    let values = split_values(list);
    if values.iter().any(String::is_empty) {
        return Err(bad(name, "empty value in the list"));
    }
    Ok(Axis {
        name: name.to_string(),
        key,
        values,
    })
}

fn split_values(list: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut depth = 0i32;
    let mut quote: Option<char> = None;
    let mut cur = String::new();
    for c in list.chars() {
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(c),
            (None, '[' | '{') => depth += 1,
            (None, ']' | '}') => depth -= 1,
            (None, ',') if depth == 0 => {
                out.push(cur.trim().to_string());
                cur.clear();
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    out.push(cur.trim().to_string());
    out
}

/// Every combination of the axes' values, the first axis varying slowest; one empty
/// assignment when there are no axes. Two axes on one key are an error.
pub fn expand(axes: &[Axis]) -> Result<Vec<Assignment>, CompareError> {
    for (i, a) in axes.iter().enumerate() {
        if axes[..i].iter().any(|b| b.key == a.key) {
            return Err(CompareError::BadGrid {
                key: a.name.clone(),
                message: format!("`{}` is on more than one --grid", a.key),
            });
        }
    }
    let mut out: Vec<Assignment> = vec![Vec::new()];
    for a in axes {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                a.values.iter().map(move |v| {
                    let mut next = prefix.clone();
                    next.push((a.name.clone(), a.key.clone(), v.clone()));
                    next
                })
            })
            .collect();
    }
    Ok(out)
}

/// The `--set` strings of one assignment. Window sizes are merged into one
/// `downsampler.windows = { … }` over `base_windows` (the config's sizes per image).
pub fn set_strings(assign: &Assignment, base_windows: &BTreeMap<String, usize>) -> Vec<String> {
    let mut sets = Vec::new();
    let mut windows = base_windows.clone();
    let mut any_window = false;
    for (_, key, value) in assign {
        match key.strip_prefix(WINDOWS_PREFIX) {
            Some(image) => {
                any_window = true;
                // A size that is not a number is passed through for the config to reject.
                match value.parse::<usize>() {
                    Ok(k) => {
                        windows.insert(image.to_string(), k);
                    }
                    Err(_) => sets.push(format!("{key}={value}")),
                }
            }
            None => sets.push(format!("{key}={value}")),
        }
    }
    if any_window {
        let items: Vec<String> = windows
            .iter()
            .map(|(k, v)| format!("{k:?} = {v}"))
            .collect();
        sets.push(format!("downsampler.windows={{ {} }}", items.join(", ")));
    }
    sets
}

/// Window sizes per image of a resolved `downsampler.windows` value (`"4_7"` or a table);
/// empty when the downsampler has none.
pub fn windows_of(value: Option<&toml::Value>) -> BTreeMap<String, usize> {
    match value {
        Some(toml::Value::String(s)) => s
            .split_once('_')
            .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)))
            .map(|(a, b)| BTreeMap::from([("signal".to_string(), a), ("range".to_string(), b)]))
            .unwrap_or_default(),
        Some(toml::Value::Table(t)) => t
            .iter()
            .filter_map(|(k, v)| Some((k.clone(), usize::try_from(v.as_integer()?).ok()?)))
            .collect(),
        _ => BTreeMap::new(),
    }
}

/// A short label of an assignment: the paper's `Sig_Rng` (e.g. `4_7`, from the merged window
/// sizes) when it sets a window size, then `name=value` for every other axis.
pub fn label(assign: &Assignment, base_windows: &BTreeMap<String, usize>) -> String {
    let mut parts = Vec::new();
    if assign.iter().any(|(_, k, _)| k.starts_with(WINDOWS_PREFIX)) {
        let mut w = base_windows.clone();
        for (_, k, v) in assign {
            if let (Some(img), Ok(n)) = (k.strip_prefix(WINDOWS_PREFIX), v.parse::<usize>()) {
                w.insert(img.to_string(), n);
            }
        }
        match (w.get("signal"), w.get("range"), w.len()) {
            (Some(s), Some(r), 2) => parts.push(format!("{s}_{r}")),
            _ => parts.extend(w.iter().map(|(k, v)| format!("{k}={v}"))),
        }
    }
    parts.extend(
        assign
            .iter()
            .filter(|(_, k, _)| !k.starts_with(WINDOWS_PREFIX))
            .map(|(n, _, v)| format!("{n}={v}")),
    );
    parts.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_split_on_top_level_commas_only() {
        let a = parse_axis("registrar.x=[1, 2],{ a = 1, b = 2 },\"p,q\",3").unwrap();
        assert_eq!(a.values, ["[1, 2]", "{ a = 1, b = 2 }", "\"p,q\"", "3"]);
        assert!(parse_axis("k_sig=4,,5").is_err());
        assert!(parse_axis("=4").is_err());
    }

    #[test]
    fn aliases_and_window_merging() {
        let axes = [
            parse_axis("k_sig=4,5").unwrap(),
            parse_axis("registrar.kind=kiss-icp,ndt").unwrap(),
        ];
        assert_eq!(axes[0].key, "downsampler.windows.signal");
        let points = expand(&axes).unwrap();
        assert_eq!(points.len(), 4);
        let base = windows_of(Some(&toml::Value::String("5_7".into())));
        let sets = set_strings(&points[3], &base);
        assert_eq!(
            sets,
            [
                "registrar.kind=ndt",
                "downsampler.windows={ \"range\" = 7, \"signal\" = 5 }"
            ]
        );
        assert_eq!(label(&points[0], &base), "4_7 registrar.kind=kiss-icp");
        let dup = [
            parse_axis("k_sig=4").unwrap(),
            parse_axis("downsampler.k_sig=5").unwrap(),
        ];
        assert!(expand(&dup).is_err());
    }
}
