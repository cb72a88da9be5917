//! The lean build (`default-features = false`) of the facade and of the C API: its dependency
//! graph holds none of the heavy crates (OpenCV bindings, ONNX Runtime, libloading, parry3d,
//! the ROS codecs and SQLite), so it compiles on a machine without libopencv-dev or libclang.

use std::process::Command;

/// Crates that only the optional features may bring in.
const HEAVY: [&str; 10] = [
    "opencv",
    "ort",
    "libloading",
    "parry3d",
    "mcap",
    "zstd",
    "bzip2",
    "lz4",
    "rusqlite",
    "libsqlite3-sys",
];

/// The names of every crate in the normal dependency graph of `package` built with `args`.
fn graph(package: &str, args: &[&str]) -> Vec<String> {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = Command::new(env!("CARGO"))
        .args([
            "tree",
            "--locked",
            "--offline",
            "-e",
            "normal",
            "--prefix",
            "none",
        ])
        .args(["--format", "{p}", "-p", package])
        .args(args)
        .current_dir(root)
        .output()
        .expect("cargo tree runs");
    assert!(
        out.status.success(),
        "cargo tree -p {package} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect()
}

#[test]
fn the_lean_graph_has_no_heavy_crate_and_the_full_one_has_them() {
    for package in ["keylo", "keylo-capi"] {
        let lean = graph(package, &["--no-default-features"]);
        assert!(lean.iter().any(|c| c == "keylo-registration"), "{lean:?}");
        let heavy: Vec<_> = lean
            .iter()
            .filter(|c| HEAVY.contains(&c.as_str()))
            .collect();
        assert!(heavy.is_empty(), "{package} lean build pulls in {heavy:?}");
        // The check means something: the default build does have them.
        let full = graph(package, &[]);
        for crate_name in ["opencv", "ort", "libloading", "parry3d", "mcap", "rusqlite"] {
            assert!(
                full.iter().any(|c| c == crate_name),
                "{package}: {crate_name}"
            );
        }
    }
}
