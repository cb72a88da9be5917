//! Replays every committed fuzz input through its target: the seed corpora
//! (`fuzz/corpus/<target>/`) and the inputs that once crashed a parser
//! (`fuzz/regressions/<target>/`). A panic fails the test naming the file.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut v: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .collect();
    v.sort();
    v
}

/// Runs every file of `kind/<target>/` through its target; returns the files that panicked
/// and how many files ran.
fn replay(kind: &str) -> (Vec<String>, usize) {
    let mut failed = Vec::new();
    let mut ran = 0;
    for target in keylo_fuzz::TARGETS {
        for file in files(&fuzz_dir().join(kind).join(target.name)) {
            let data = std::fs::read(&file).expect("committed fuzz input is readable");
            ran += 1;
            if catch_unwind(AssertUnwindSafe(|| (target.run)(&data))).is_err() {
                failed.push(file.display().to_string());
            }
        }
    }
    (failed, ran)
}

#[test]
fn every_seed_corpus_file_runs_without_panicking() {
    let (failed, ran) = replay("corpus");
    assert!(ran > 0, "no corpus under {}", fuzz_dir().display());
    assert!(failed.is_empty(), "panicked on {failed:#?}");
}

#[test]
fn every_regression_input_runs_without_panicking() {
    let (failed, _) = replay("regressions");
    assert!(failed.is_empty(), "panicked on {failed:#?}");
}

#[test]
fn every_target_has_a_seed_corpus() {
    for target in keylo_fuzz::TARGETS {
        let dir = fuzz_dir().join("corpus").join(target.name);
        assert!(!files(&dir).is_empty(), "no seeds in {}", dir.display());
    }
}
