//! Helpers for the CLI tests: run the real `keylo` binary.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn keylo(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_keylo"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the keylo binary runs")
}

/// Runs `keylo` with a whitespace-separated argument line (test paths hold no spaces).
#[allow(dead_code)]
pub fn keylo_line(line: &str, cwd: &Path) -> Output {
    let args: Vec<&str> = line.split_whitespace().collect();
    keylo(&args, cwd)
}

#[allow(dead_code)]
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[allow(dead_code)]
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A small simulated frame folder (OS1-64, 512 columns) for fast tests.
#[allow(dead_code)]
pub fn small_sim(dir: &Path, frames: usize) {
    std::fs::create_dir_all(dir).expect("create the data folder");
    let out = dir.to_str().expect("utf-8 temp path");
    let o = keylo(
        &[
            "sim",
            "--scene",
            "lab",
            "--frames",
            &frames.to_string(),
            "--out",
            out,
            "--set",
            "sensor=os1-64",
            "--set",
            "columns=512",
            "-q",
        ],
        dir,
    );
    assert!(o.status.success(), "sim failed: {}", stderr(&o));
}

/// Asserts exit status `code`, no panic, and that stderr contains `needle`.
#[allow(dead_code)]
pub fn expect_failure(o: &Output, code: i32, needle: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{e}");
    assert!(!e.contains("panicked"), "panic: {e}");
    assert!(e.contains(needle), "stderr lacks `{needle}`: {e}");
}

/// The rows of a CSV file without quoted fields, as column → value.
#[allow(dead_code)]
pub fn read_csv(p: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(p).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

/// The path of `configs/<rel>` in the repository.
#[allow(dead_code)]
pub fn config(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../configs")
        .join(rel)
        .display()
        .to_string()
}

/// The repository's root folder.
#[allow(dead_code)]
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Compiles C (or C++, by the extension) `source` into the shared library `out` with
/// `defines` (`-D` flags).
#[allow(dead_code)]
pub fn compile_plugin(source: &Path, out: &Path, defines: &[&str]) {
    let cpp = source.extension().is_some_and(|e| e == "cpp");
    let compiler = cc::Build::new()
        .cargo_metadata(false)
        .cpp(cpp)
        .opt_level(2)
        .debug(false)
        .target(env!("KEYLO_TEST_TARGET"))
        .host(env!("KEYLO_TEST_TARGET"))
        .try_get_compiler()
        .expect("a C compiler");
    let mut cmd = compiler.to_command();
    let std = if cpp { "-std=c++17" } else { "-std=c99" };
    cmd.args(["-shared", "-fPIC", std, "-Wall", "-Werror"])
        .arg("-I")
        .arg(root().join("crates/keylo-plugin/include"))
        .args(defines.iter().map(|d| format!("-D{d}")))
        .arg(source)
        .arg("-o")
        .arg(out);
    let o = cmd.output().expect("the C compiler runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
