//! `shard.json`: what one shard of a study was given and what it finished. Written at the
//! shard's start and again at its end (each time whole, [`crate::atomic`]); `merge` reads it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::Value;
use sha2::{Digest, Sha256};

use super::{Shard, ShardError};

/// The manifest's file name in a shard folder.
pub const FILE: &str = "shard.json";
/// The manifest format this keylo writes and merges; a shard of another format is refused.
pub const FORMAT: &str = "keylo-shard/1";

/// One shard's manifest.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Manifest {
    pub format: String,
    /// The keylo version that wrote it.
    pub keylo: String,
    /// `compare`, `keypoints eval` or `keypoints sweep`.
    pub command: String,
    /// Hash of the study (command, [`Manifest::detail`] and every item): shards of one study
    /// share it.
    pub study: String,
    pub shard: usize,
    pub shards: usize,
    /// Every item of the study, in the order a single process does them.
    pub study_items: Vec<String>,
    /// This shard's items, in study order.
    pub items: Vec<String>,
    /// Whether every item of this shard is finished.
    pub complete: bool,
    /// What merge needs to write the tables (the plans, the settings); part of the study.
    pub detail: Value,
    /// Per finished item, what the command records of it (its outcome, its rows).
    pub results: BTreeMap<String, Value>,
    /// Wall-clock seconds of this shard's last invocation.
    pub seconds: f64,
}

/// The hash naming a study: SHA-256 of its command, detail and item list (16 hex digits).
pub fn study_id(command: &str, detail: &Value, items: &[String]) -> String {
    let canonical = serde_json::json!({ "command": command, "detail": detail, "items": items });
    let digest = Sha256::digest(canonical.to_string().as_bytes());
    digest.iter().take(8).map(|b| format!("{b:02x}")).collect()
}

impl Manifest {
    /// A fresh manifest of `shard` of a study whose items' shards are `assigned`.
    pub fn new(
        command: &str,
        shard: Shard,
        detail: Value,
        study_items: Vec<String>,
        assigned: &[usize],
    ) -> Self {
        let items = study_items
            .iter()
            .zip(assigned)
            .filter(|(_, s)| **s == shard.index)
            .map(|(id, _)| id.clone())
            .collect();
        Self {
            format: FORMAT.into(),
            keylo: env!("CARGO_PKG_VERSION").into(),
            command: command.into(),
            study: study_id(command, &detail, &study_items),
            shard: shard.index,
            shards: shard.count,
            study_items,
            items,
            complete: false,
            detail,
            results: BTreeMap::new(),
            seconds: 0.0,
        }
    }

    /// The manifest in `dir`; an error names the folder and what is wrong with it.
    pub fn read(dir: &Path) -> Result<Self, ShardError> {
        let path = dir.join(FILE);
        let not = |why: String| ShardError::NotAShard {
            dir: dir.to_path_buf(),
            why,
        };
        let text = std::fs::read_to_string(&path).map_err(|e| {
            not(format!(
                "no readable {FILE} ({e}): not the --out of a `--shard` run"
            ))
        })?;
        let value: Value =
            serde_json::from_str(&text).map_err(|e| not(format!("{FILE} is not JSON: {e}")))?;
        let format = value["format"].as_str().unwrap_or("none");
        if format != FORMAT {
            return Err(not(format!(
                "{FILE} is of format `{format}` (keylo {}), this keylo {} merges `{FORMAT}`: \
                 run the shard again with this keylo",
                value["keylo"].as_str().unwrap_or("unknown"),
                env!("CARGO_PKG_VERSION")
            )));
        }
        serde_json::from_value(value).map_err(|e| not(format!("{FILE}: {e}")))
    }

    /// Writes the manifest into `dir` (whole or not at all).
    pub fn write(&self, dir: &Path) -> Result<(), ShardError> {
        let path = dir.join(FILE);
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        crate::atomic::write(&path, text).map_err(|e| ShardError::io(path, e))
    }

    /// The manifest a shard starts from in `out`: this one, with the results of an earlier
    /// run of the same shard (a resume). A manifest of another study or shard is refused.
    pub fn resume_in(mut self, out: &Path) -> Result<Self, ShardError> {
        if !out.join(FILE).exists() {
            return Ok(self);
        }
        let earlier = Self::read(out).map_err(|e| ShardError::OutTaken {
            dir: out.to_path_buf(),
            why: e.to_string(),
        })?;
        let taken = |why: String| ShardError::OutTaken {
            dir: out.to_path_buf(),
            why,
        };
        if earlier.command != self.command || earlier.study != self.study {
            return Err(taken(format!(
                "it holds shard {}/{} of another study ({} {}; this is {} {})",
                earlier.shard,
                earlier.shards,
                earlier.command,
                earlier.study,
                self.command,
                self.study
            )));
        }
        if (earlier.shard, earlier.shards) != (self.shard, self.shards) {
            return Err(taken(format!(
                "it holds shard {}/{} of this study, not {}/{}",
                earlier.shard, earlier.shards, self.shard, self.shards
            )));
        }
        self.results = earlier.results;
        self.results.retain(|id, _| self.items.contains(id));
        Ok(self)
    }
}

/// The folders of `dirs`, each with its manifest.
pub fn read_all(dirs: &[PathBuf]) -> Result<Vec<(PathBuf, Manifest)>, ShardError> {
    dirs.iter()
        .map(|d| Manifest::read(d).map(|m| (d.clone(), m)))
        .collect()
}
