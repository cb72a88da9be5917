//! Checking that shard folders make one complete study, and finding each item's result.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use super::manifest::{read_all, Manifest};
use super::ShardError;

/// A whole study, joined from its shards.
#[derive(Debug)]
pub struct Joined {
    /// The study's detail (plans, settings), as every shard recorded it.
    pub detail: Value,
    /// Every item in study order, with the folder of the shard that did it and its result.
    pub items: Vec<(String, PathBuf, Value)>,
    /// Each shard's folder and its wall-clock seconds.
    pub shards: Vec<(PathBuf, f64)>,
    /// The study's hash.
    pub study: String,
}

impl Joined {
    /// `out/merged.json`: the study, its items, each shard's folder and seconds, their sum.
    pub fn write_note(&self, out: &Path) -> Result<(), ShardError> {
        let shards: Vec<Value> = self
            .shards
            .iter()
            .map(|(d, s)| serde_json::json!({"dir": d.display().to_string(), "seconds": s}))
            .collect();
        let summed: f64 = self.shards.iter().map(|(_, s)| s).sum();
        let note = serde_json::json!({"study": self.study, "items": self.items.len(),
                                      "shards": shards, "shard_seconds_sum": summed});
        let path = out.join("merged.json");
        let text = serde_json::to_string_pretty(&note).unwrap_or_default();
        crate::atomic::write(&path, text).map_err(|e| ShardError::io(path, e))
    }
}

/// Reads the manifests of `dirs` and checks that they are the shards of one `command` study,
/// all N of them, complete, every item done exactly once; an error names the shard and item.
pub fn join(command: &str, dirs: &[PathBuf]) -> Result<Joined, ShardError> {
    if dirs.is_empty() {
        return Err(ShardError::Mismatch(
            "no shard folders given: name every shard's --out".into(),
        ));
    }
    let all = read_all(dirs)?;
    let (first_dir, first) = &all[0];
    let name = |d: &Path, m: &Manifest| format!("shard {}/{} ({})", m.shard, m.shards, d.display());
    for (d, m) in &all {
        if m.command != command {
            return Err(ShardError::Mismatch(format!(
                "{} is a shard of `keylo {}`, not of `keylo {command}`",
                name(d, m),
                m.command
            )));
        }
        if m.study != first.study || m.shards != first.shards {
            return Err(ShardError::Mismatch(format!(
                "{} and {} belong to different studies (study {} of {} shards against {} of {}): \
                 other configs, data, settings or shard counts",
                name(first_dir, first),
                name(d, m),
                first.study,
                first.shards,
                m.study,
                m.shards
            )));
        }
    }
    let mut by_index: BTreeMap<usize, &(PathBuf, Manifest)> = BTreeMap::new();
    for entry in &all {
        let (d, m) = entry;
        if let Some((other, _)) = by_index.insert(m.shard, entry) {
            return Err(ShardError::Mismatch(format!(
                "shard {}/{} is given twice: {} and {}",
                m.shard,
                m.shards,
                other.display(),
                d.display()
            )));
        }
    }
    let missing: Vec<String> = (0..first.shards)
        .filter(|i| !by_index.contains_key(i))
        .map(|i| format!("{i}/{}", first.shards))
        .collect();
    if !missing.is_empty() {
        return Err(ShardError::Mismatch(format!(
            "shard(s) {} of study {} missing: give every shard's folder",
            missing.join(", "),
            first.study
        )));
    }
    for (d, m) in &all {
        if !m.complete {
            let done = m
                .items
                .iter()
                .filter(|i| m.results.contains_key(*i))
                .count();
            return Err(ShardError::Mismatch(format!(
                "{} is incomplete ({done} of {} items done): run it again with the same command \
                 (finished items are skipped)",
                name(d, m),
                m.items.len()
            )));
        }
    }
    let mut found: BTreeMap<&str, (&PathBuf, &Manifest)> = BTreeMap::new();
    for (d, m) in &all {
        for id in m.results.keys() {
            if let Some((other, om)) = found.insert(id, (d, m)) {
                return Err(ShardError::Mismatch(format!(
                    "item `{id}` was done twice: by {} and by {}",
                    name(other, om),
                    name(d, m)
                )));
            }
        }
    }
    let mut items = Vec::new();
    for id in &first.study_items {
        let Some((d, m)) = found.get(id.as_str()) else {
            return Err(ShardError::Mismatch(format!(
                "item `{id}` of study {} is in no shard's results",
                first.study
            )));
        };
        items.push(((*id).clone(), (*d).clone(), m.results[id].clone()));
    }
    if let Some(extra) = found
        .keys()
        .find(|k| !first.study_items.iter().any(|i| i == *k))
    {
        return Err(ShardError::Mismatch(format!(
            "item `{extra}` ({}) is not an item of study {}",
            name(found[extra].0, found[extra].1),
            first.study
        )));
    }
    Ok(Joined {
        detail: first.detail.clone(),
        items,
        shards: by_index
            .values()
            .map(|(d, m)| (d.clone(), m.seconds))
            .collect(),
        study: first.study.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shard::{partition, Shard};

    fn study(dir: &Path, shards: usize, detail: Value) -> Vec<PathBuf> {
        let ids: Vec<String> = (0..5).map(|i| format!("item{i}")).collect();
        let assigned = partition(&[1.0; 5], shards);
        (0..shards)
            .map(|i| {
                let d = dir.join(format!("s{i}"));
                std::fs::create_dir_all(&d).unwrap();
                let shard = Shard {
                    index: i,
                    count: shards,
                };
                let mut m = Manifest::new("compare", shard, detail.clone(), ids.clone(), &assigned);
                for id in m.items.clone() {
                    m.results.insert(id, Value::from(1));
                }
                m.complete = true;
                m.write(&d).unwrap();
                d
            })
            .collect()
    }

    fn err(command: &str, dirs: &[PathBuf]) -> String {
        join(command, dirs).unwrap_err().to_string()
    }

    #[test]
    fn a_whole_study_joins_in_study_order() {
        let tmp = tempfile::tempdir().unwrap();
        let dirs = study(tmp.path(), 2, Value::from("a"));
        let j = join("compare", &[dirs[1].clone(), dirs[0].clone()]).unwrap();
        let ids: Vec<&str> = j.items.iter().map(|(i, _, _)| i.as_str()).collect();
        assert_eq!(ids, ["item0", "item1", "item2", "item3", "item4"]);
        assert_eq!(j.shards.len(), 2);
    }

    #[test]
    fn wrong_sets_of_shards_are_named() {
        let tmp = tempfile::tempdir().unwrap();
        let a = study(&tmp.path().join("a"), 2, Value::from("a"));
        let b = study(&tmp.path().join("b"), 2, Value::from("b"));
        let three = study(&tmp.path().join("c"), 3, Value::from("a"));
        assert!(err("compare", &[a[0].clone(), b[1].clone()]).contains("different studies"));
        assert!(err("compare", &[a[0].clone(), three[1].clone()]).contains("different studies"));
        let e = err("compare", &[a[0].clone()]);
        assert!(e.contains("shard(s) 1/2") && e.contains("missing"), "{e}");
        assert!(err("compare", &[a[0].clone(), a[0].clone()]).contains("given twice"));
        assert!(err("keypoints eval", &a).contains("not of `keylo keypoints eval`"));
        // An item done by two shards.
        let mut m = Manifest::read(&a[1]).unwrap();
        let theirs = Manifest::read(&a[0]).unwrap().items[0].clone();
        m.results.insert(theirs.clone(), Value::from(1));
        m.write(&a[1]).unwrap();
        let e = err("compare", &a);
        assert!(e.contains(&format!("`{theirs}` was done twice")), "{e}");
        // An unfinished shard.
        m.results.remove(&theirs);
        m.complete = false;
        m.write(&a[1]).unwrap();
        assert!(err("compare", &a).contains("incomplete"));
        // A folder of an older keylo (another manifest format) and one without a manifest.
        std::fs::write(
            a[1].join("shard.json"),
            r#"{"format":"keylo-shard/0","keylo":"0.1.0"}"#,
        )
        .unwrap();
        let e = err("compare", &a);
        assert!(e.contains("keylo-shard/0") && e.contains("0.1.0"), "{e}");
        let e = err("compare", &[tmp.path().to_path_buf()]);
        assert!(e.contains("no readable shard.json"), "{e}");
    }
}
