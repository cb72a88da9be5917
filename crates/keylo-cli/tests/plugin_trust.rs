//! A config from a stranger runs no code of theirs: the libraries a config names itself
//! (`[plugins] dirs`, `onnxruntime`) load only with `--trust-plugins`. The library used here
//! leaves a marker file from its load-time constructor, so the marker's absence proves that
//! nothing was loaded (docs/plugins.md, "Trust").

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{compile_plugin, small_sim, stderr};

struct Setup {
    dir: tempfile::TempDir,
}

impl Setup {
    /// `shared/` holds a config as someone might share it, its library in `shared/p/`;
    /// `data/` a three-frame simulated sequence.
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let shared = dir.path().join("shared");
        std::fs::create_dir_all(shared.join("p")).unwrap();
        std::fs::create_dir_all(dir.path().join("installed")).unwrap();
        let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/plugins/marker.c");
        compile_plugin(&source, &shared.join("p/libmarker.so"), &[]);
        std::fs::write(
            shared.join("plugin.toml"),
            "[plugins]\ndirs = [\"p\"]\n[detector]\nkind = \"plugin:marker\"\n",
        )
        .unwrap();
        std::fs::write(
            shared.join("runtime.toml"),
            "[detector]\nkind = \"superpoint\"\nonnxruntime = \"p/libmarker.so\"\n",
        )
        .unwrap();
        small_sim(&dir.path().join("data"), 3);
        Self { dir }
    }

    fn path(&self, p: &str) -> PathBuf {
        self.dir.path().join(p)
    }

    fn marker(&self) -> PathBuf {
        self.path("marker")
    }

    /// `keylo ARGS` in the temp folder, with an empty installed-plugin folder.
    fn keylo(&self, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_keylo"))
            .args(args)
            .current_dir(self.dir.path())
            .env("KEYLO_TEST_MARKER", self.marker())
            .env("KEYLO_PLUGIN_PATH", self.path("installed"))
            .env("HOME", self.path("home"))
            .output()
            .expect("the keylo binary runs")
    }

    /// Asserts `o` is a refusal naming the library and the opt-in, and nothing was loaded.
    fn refused(&self, o: &Output, named: &str) {
        let e = stderr(o);
        assert_ne!(o.status.code(), Some(0), "{e}");
        assert!(!e.contains("panicked"), "{e}");
        assert!(e.contains(named), "the library is named: {e}");
        assert!(e.contains("--trust-plugins"), "the opt-in is named: {e}");
        assert!(!self.marker().exists(), "the library's code ran: {e}");
    }
}

#[test]
fn a_configs_own_plugin_folder_loads_nothing_without_the_opt_in() {
    let s = Setup::new();
    let lib = "p/libmarker.so ([plugins] dirs)";
    for line in [
        "run shared/plugin.toml --data data --out o1 -q",
        "config show shared/plugin.toml",
        "compare shared/plugin.toml --data data --out c1 -q",
        "info data --image 0 --out i --config shared/plugin.toml",
    ] {
        let args: Vec<&str> = line.split(' ').collect();
        s.refused(&s.keylo(&args), lib);
    }
    // Listing shows it without loading it.
    let o = s.keylo(&["plugins", "list", "shared/plugin.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("libmarker.so"), "{}", stderr(&o));
    assert!(!s.marker().exists());
    // With the opt-in it is loaded (and then refused as no plugin: it has no entry symbol).
    let o = s.keylo(&[
        "run",
        "shared/plugin.toml",
        "--data",
        "data",
        "--out",
        "o2",
        "-q",
        "--trust-plugins",
    ]);
    assert!(s.marker().exists(), "{}", stderr(&o));
    assert!(stderr(&o).contains("keylo_plugin_entry"), "{}", stderr(&o));
}

#[test]
fn a_plugin_name_with_a_path_in_it_is_refused_trusted_or_not() {
    let s = Setup::new();
    // Names that would reach the config's library from an installed folder's search.
    let abs = s.path("shared/p/libmarker");
    for name in ["../shared/p/libmarker", abs.to_str().unwrap()] {
        let toml = format!("[detector]\nkind = \"plugin:{name}\"\n");
        std::fs::write(s.path("path.toml"), toml).unwrap();
        for trust in [false, true] {
            let mut args = vec!["run", "path.toml", "--data", "data", "--out", "o", "-q"];
            if trust {
                args.push("--trust-plugins");
            }
            let o = s.keylo(&args);
            let e = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{e}");
            assert!(e.contains("a plugin name is letters, digits"), "{e}");
            assert!(!s.marker().exists(), "{e}");
        }
    }
}

#[test]
fn an_onnxruntime_path_in_a_config_is_refused_without_the_opt_in() {
    let s = Setup::new();
    let o = s.keylo(&[
        "run",
        "shared/runtime.toml",
        "--data",
        "data",
        "--out",
        "o",
        "-q",
    ]);
    s.refused(&o, "p/libmarker.so (detector.onnxruntime)");
    // The same in a keypoint evaluation's settings.
    std::fs::write(
        s.path("shared/eval.toml"),
        "[params.superpoint]\nonnxruntime = \"p/libmarker.so\"\n",
    )
    .unwrap();
    let o = s.keylo(&[
        "keypoints",
        "eval",
        "--data",
        "data",
        "--config",
        "shared/eval.toml",
        "--combos",
        "ORB_ORB",
        "--out",
        "k",
        "-q",
    ]);
    s.refused(&o, "p/libmarker.so (params.superpoint.onnxruntime)");
}

#[test]
fn installed_plugins_load_without_the_opt_in_and_are_logged() {
    let s = Setup::new();
    std::fs::copy(
        s.path("shared/p/libmarker.so"),
        s.path("installed/libmarker.so"),
    )
    .unwrap();
    std::fs::write(
        s.path("mine.toml"),
        "[detector]\nkind = \"plugin:marker\"\n",
    )
    .unwrap();
    let o = s.keylo(&["run", "mine.toml", "--data", "data", "--out", "o", "-v"]);
    assert!(s.marker().exists(), "{}", stderr(&o));
    let installed = s.path("installed/libmarker.so");
    let logged = format!("loading plugin library {}", installed.display());
    assert!(stderr(&o).contains(&logged), "{}", stderr(&o));
    // The user's own `--dir` in `plugins list` is trusted too.
    std::fs::remove_file(s.marker()).unwrap();
    let o = s.keylo(&["plugins", "list", "--dir", "shared/p"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(s.marker().exists(), "{}", stderr(&o));
}
