//! Sharded studies (`--shard I/N`, `… merge`): one study (`keylo compare`, `keylo keypoints
//! eval` or `sweep`) split into N deterministic parts that run anywhere (a Slurm array, a
//! Kubernetes Indexed Job), each into its own folder with a [`manifest`], and joined again by
//! [`merge`] into the tables a single process would write. See docs/scale-out.md.
//!
//! Every shard computes the whole study's item list and the same partition of it (greedy
//! longest-processing-time on the items' expected costs), so shards need no coordination.

pub mod error;
pub mod manifest;
pub mod merge;

use std::path::Path;
use std::str::FromStr;

pub use error::ShardError;

/// Shard `index` (0-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl FromStr for Shard {
    type Err = ShardError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = |why: String| ShardError::BadSpec {
            given: s.to_string(),
            why,
        };
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| bad("expected I/N, e.g. 0/4 (shard I of N, counted from 0)".into()))?;
        let parse = |v: &str, what: &str| {
            v.trim()
                .parse::<usize>()
                .map_err(|_| bad(format!("{what} `{v}` is not a whole number")))
        };
        let (index, count) = (parse(i, "I")?, parse(n, "N")?);
        if count == 0 {
            return Err(bad("N must be at least 1".into()));
        }
        if index >= count {
            return Err(bad(format!(
                "shard {index} does not exist: shards are counted from 0, so {count} shards are 0 to {}",
                count - 1
            )));
        }
        Ok(Self { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// The shard of every item: the most expensive first, each to the shard with the least
/// expected cost so far (ties: the lower index). Deterministic for the same costs.
pub fn partition(costs: &[f64], count: usize) -> Vec<usize> {
    let count = count.max(1);
    let mut order: Vec<usize> = (0..costs.len()).collect();
    let cost = |i: usize| {
        costs
            .get(i)
            .copied()
            .filter(|c| c.is_finite())
            .unwrap_or(0.0)
    };
    order.sort_by(|&a, &b| cost(b).total_cmp(&cost(a)).then(a.cmp(&b)));
    let mut load = vec![0.0_f64; count];
    let mut out = vec![0; costs.len()];
    for i in order {
        let mut best = 0;
        for (s, l) in load.iter().enumerate() {
            if *l < load[best] {
                best = s;
            }
        }
        load[best] += cost(i).max(f64::MIN_POSITIVE);
        out[i] = best;
    }
    out
}

/// Bytes under `path` (a file's size, or every file's below a folder): the expected cost of
/// reading it, up to a factor.
pub fn data_size(path: &Path) -> u64 {
    let Ok(meta) = std::fs::metadata(path) else {
        return 0;
    };
    if !meta.is_dir() {
        return meta.len();
    }
    std::fs::read_dir(path)
        .map(|entries| entries.flatten().map(|e| data_size(&e.path())).sum())
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_bad_ones_say_why() {
        assert_eq!(
            "2/4".parse::<Shard>().unwrap(),
            Shard { index: 2, count: 4 }
        );
        for (bad, says) in [
            ("5/4", "0 to 3"),
            ("4/4", "0 to 3"),
            ("1/0", "at least 1"),
            ("x/4", "`x`"),
            ("3", "expected I/N"),
        ] {
            let e = bad.parse::<Shard>().unwrap_err().to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn partition_balances_expected_cost_and_is_deterministic() {
        let costs = [9.0, 1.0, 1.0, 4.0, 4.0, 1.0, 2.0, 8.0];
        let p = partition(&costs, 3);
        assert_eq!(p, partition(&costs, 3));
        let mut load = [0.0; 3];
        for (i, s) in p.iter().enumerate() {
            load[*s] += costs[i];
        }
        // 30 in all: LPT gives 10/10/10 here.
        assert_eq!(load, [10.0, 10.0, 10.0], "{p:?}");
        // Every item in exactly one shard; more shards than items leave some empty.
        assert_eq!(partition(&[1.0, 1.0], 4), vec![0, 1]);
        assert_eq!(partition(&[], 2), Vec::<usize>::new());
    }
}
