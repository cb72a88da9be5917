//! Run-time plugins from the command line: the C example plugin built with `cc` and run from
//! its example config, `keylo plugins list/check`, and the loader's bad-input errors.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{compile_plugin, expect_failure, root, small_sim, stderr, stdout};

/// The test plugin source `tests/fixtures/plugins/NAME`.
fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/plugins")
        .join(name)
}

/// A temp folder with `plugins/libc-peaks.so` and the faulty test plugins, and `data/`, a
/// five-frame simulated sequence.
struct Setup {
    dir: tempfile::TempDir,
}

impl Setup {
    /// A temp folder with an empty `plugins/`.
    fn empty() -> Self {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("plugins")).unwrap();
        Self { dir }
    }

    fn new() -> Self {
        let s = Self::empty();
        let plugins = s.plugins();
        compile_plugin(
            &root().join("plugins/c-peaks/peaks.c"),
            &plugins.join("libc-peaks.so"),
            &[],
        );
        let faulty = fixture("faulty.c");
        for (name, flag) in [
            ("bad-abi", "ABI=999"),
            ("no-entry", "NO_ENTRY"),
            ("outside", "FAULT_OUTSIDE"),
            ("nan", "FAULT_NAN"),
        ] {
            let define = format!("PLUGIN_NAME=\"{name}\"");
            compile_plugin(
                &faulty,
                &plugins.join(format!("lib{name}.so")),
                &[&define, flag],
            );
        }
        small_sim(&s.dir.path().join("data"), 5);
        s
    }

    fn plugins(&self) -> PathBuf {
        self.dir.path().join("plugins")
    }

    /// `keylo ARGS` with KEYLO_PLUGIN_PATH = the plugin folder and HOME inside the temp dir.
    fn keylo(&self, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_keylo"))
            .args(args)
            .current_dir(self.dir.path())
            .env("KEYLO_PLUGIN_PATH", self.plugins())
            .env("HOME", self.dir.path().join("home"))
            .output()
            .expect("the keylo binary runs")
    }

    /// `keylo run` of the C example config on the simulated data with extra `--set`s.
    fn run(&self, sets: &[&str]) -> Output {
        self.run_config("lab-c-peaks-kiss-icp.toml", sets)
    }

    /// `keylo run configs/examples/NAME` on the simulated data with extra `--set`s.
    fn run_config(&self, name: &str, sets: &[&str]) -> Output {
        let config = root().join("configs/examples").join(name);
        let (data, out) = (self.dir.path().join("data"), self.dir.path().join("out"));
        let mut args = vec![
            "run".to_string(),
            config.display().to_string(),
            "--data".into(),
            data.display().to_string(),
            "--out".into(),
            out.display().to_string(),
            "-q".into(),
        ];
        for s in sets {
            args.push("--set".into());
            args.push((*s).into());
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        self.keylo(&args)
    }
}

#[test]
fn c_plugin_runs_from_its_example_config() {
    check_run(&Setup::new(), "lab-c-peaks-kiss-icp.toml", "plugin:c-peaks");
}

/// Skipped (with a note) only where no C++ compiler is installed; the C tests need a C one.
#[test]
fn cpp_plugin_runs_from_its_example_config() {
    let s = Setup::new();
    let has_cpp = cc::Build::new()
        .cargo_metadata(false)
        .cpp(true)
        .target(env!("KEYLO_TEST_TARGET"))
        .host(env!("KEYLO_TEST_TARGET"))
        .opt_level(0)
        .try_get_compiler()
        .is_ok_and(|c| {
            c.to_command()
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        });
    if !has_cpp {
        eprintln!("note: no C++ compiler: the C++ example plugin is not tested here");
        return;
    }
    compile_plugin(
        &root().join("plugins/cpp-gradient/gradient.cpp"),
        &s.plugins().join("libcpp-gradient.so"),
        &[],
    );
    check_run(&s, "lab-cpp-gradient-kiss-icp.toml", "plugin:cpp-gradient");
}

/// Runs example config `name` on five frames: five finite poses, keypoints from `kind`.
fn check_run(s: &Setup, name: &str, kind: &str) {
    let o = s.run_config(name, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = s.dir.path().join("out");
    let tum = std::fs::read_to_string(out.join("trajectory.tum")).unwrap();
    let rows: Vec<Vec<f64>> = tum
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 5, "{tum}");
    assert!(rows.iter().flatten().all(|v| v.is_finite()));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    let kps = summary["mean_keypoints"].as_f64().unwrap_or_default();
    assert!(kps > 50.0, "{summary}");
    // The config a run writes names the plugin and where it was found.
    let written = std::fs::read_to_string(out.join("config.toml")).unwrap();
    assert!(written.contains(&format!("kind = \"{kind}\"")), "{written}");
    assert!(written.contains("[plugins]"), "{written}");
}

#[test]
fn plugins_list_and_check_show_name_version_kinds_path_abi() {
    let s = Setup::new();
    let o = s.keylo(&["plugins", "list"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let line = text
        .lines()
        .find(|l| l.starts_with("plugin:c-peaks "))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        line.contains("0.1.0") && line.contains(" 3 ") && line.contains("detector"),
        "{line}"
    );
    assert!(line.contains("libc-peaks.so"), "{line}");
    assert!(text.contains("KEYLO_PLUGIN_PATH"), "{text}");
    // The broken ones are reported, not listed.
    let e = stderr(&o);
    assert!(e.contains("libbad-abi.so") && e.contains("999"), "{e}");

    let file = s.plugins().join("libc-peaks.so");
    let o = s.keylo(&["plugins", "check", file.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("ok: detector `plugin:c-peaks`"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn abi_version_mismatch_is_refused_with_both_versions() {
    let s = Setup::new();
    let o = s.run(&["detector.kind=plugin:bad-abi"]);
    expect_failure(&o, 2, "plugin ABI version 999 is not supported");
    expect_failure(&o, 2, "supports ABI versions 1, 2, 3");
    let file = s.plugins().join("libbad-abi.so");
    let o = s.keylo(&["plugins", "check", file.to_str().unwrap()]);
    expect_failure(&o, 2, "ABI version 999");
}

#[test]
fn missing_entry_symbol_is_refused() {
    let s = Setup::new();
    let o = s.run(&["detector.kind=plugin:no-entry"]);
    expect_failure(&o, 2, "libno-entry.so: no symbol `keylo_plugin_entry`");
}

#[test]
fn a_plugin_in_the_wrong_stage_is_refused() {
    let s = Setup::new();
    let o = s.run(&["registrar.kind=plugin:c-peaks"]);
    expect_failure(&o, 2, "plugin `c-peaks`");
    expect_failure(&o, 2, "offers no registrar; it offers: detector");
}

#[test]
fn keypoints_outside_the_image_or_nan_are_rejected_naming_the_plugin() {
    let s = Setup::new();
    let o = s.run(&["detector.kind=plugin:outside"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("plugin `outside`") && e.contains("lies outside the"),
        "{e}"
    );
    assert!(!e.contains("panicked"), "{e}");
    let o = s.run(&["detector.kind=plugin:nan"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("plugin `nan`") && e.contains("non-finite coordinate"),
        "{e}"
    );
}

#[test]
fn a_missing_plugin_lists_the_searched_folders() {
    let s = Setup::new();
    let o = s.run(&["detector.kind=plugin:nowhere"]);
    expect_failure(
        &o,
        2,
        "plugin `nowhere` not found: looked for libnowhere.so, nowhere.so",
    );
    let e = stderr(&o);
    assert!(e.contains("target/plugins ([plugins] dirs)"), "{e}");
    assert!(
        e.contains(&format!("{} (KEYLO_PLUGIN_PATH)", s.plugins().display())),
        "{e}"
    );
    assert!(e.contains(".local/lib/keylo/plugins (default)"), "{e}");
}

#[test]
fn bad_plugin_parameters_are_reported_by_the_plugin() {
    let s = Setup::new();
    let o = s.run(&["detector.cell=1"]);
    expect_failure(&o, 2, "plugin `c-peaks`");
    expect_failure(&o, 2, "configure configuration rejected");
}

/// `plugins/` with the downsampler fixtures `v1-grid` (built against the frozen version-1
/// header) and `scan-all` (version 2), and `bins/`: three simulated frames as KITTI `.bin`
/// files, an unorganised source whose frames carry every point of the file.
fn scan_setup() -> Setup {
    let s = Setup::empty();
    for (name, source) in [("v1-grid", "v1_downsampler.c"), ("scan-all", "scan_all.c")] {
        let define = format!("PLUGIN_NAME=\"{name}\"");
        let lib = s.plugins().join(format!("lib{name}.so"));
        compile_plugin(&fixture(source), &lib, &[&define]);
    }
    let sim =
        "sim --frames 3 --format kitti-bin --out bins --set sensor=os1-64 --set columns=512 -q";
    let o = s.keylo(&sim.split_whitespace().collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(
        s.dir.path().join("scan.toml"),
        "[downsampler]\nkind = \"passthrough\"\n\n[registrar]\nkind = \"kiss-icp\"\n",
    )
    .unwrap();
    s
}

impl Setup {
    /// `keylo run scan.toml --data bins` with `downsampler.kind` and more `--set`s: the
    /// summary's mean points per registered cloud.
    fn mean_cloud_points(&self, downsampler: &str, sets: &[&str]) -> f64 {
        let out = self.dir.path().join(format!("out-{downsampler}"));
        let kind = format!("downsampler.kind={downsampler}");
        let mut args = vec!["run", "scan.toml", "--data", "bins", "-q", "--set", &kind];
        args.extend(sets.iter().flat_map(|s| ["--set", s]));
        args.extend(["--out", out.to_str().unwrap()]);
        let o = self.keylo(&args);
        assert!(o.status.success(), "{downsampler}: {}", stderr(&o));
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
        summary["mean_cloud_points"]
            .as_f64()
            .unwrap_or_else(|| panic!("{summary}"))
    }
}

#[test]
fn a_plugin_built_against_abi_v1_still_loads_and_runs() {
    let s = scan_setup();
    let o = s.keylo(&["plugins", "list"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let line = text
        .lines()
        .find(|l| l.starts_with("plugin:v1-grid "))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        line.contains(" 1 ") && line.contains("downsampler"),
        "{line}"
    );
    // It reads the version-1 prefix of the frame: the grid, one point per valid pixel, the
    // same cloud as the built-in downsampler keeping the nearest point of each pixel.
    let v1 = s.mean_cloud_points("plugin:v1-grid", &[]);
    let nearest = s.mean_cloud_points("passthrough", &["downsampler.pixel_points=nearest"]);
    assert!(
        v1 > 0.0 && v1 == nearest,
        "v1 plugin {v1}, nearest {nearest}"
    );
}

#[test]
fn an_abi_v2_downsampler_sees_every_point_of_an_unorganised_scan() {
    let s = scan_setup();
    let bins = s.dir.path().join("bins/velodyne");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&bins)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), 3);
    let mut total = 0;
    for f in &files {
        let points = keylo::io::kitti_bin::read_kitti_bin(f).unwrap();
        assert!(points.iter().flatten().all(|v| v.is_finite()));
        total += points.len();
    }
    let all = s.mean_cloud_points("plugin:scan-all", &[]);
    assert_eq!(all, total as f64 / 3.0, "every point of the files");
    // More than the grid shows: pixels that hold several points give all of them.
    let nearest = s.mean_cloud_points("passthrough", &["downsampler.pixel_points=nearest"]);
    assert!(all > nearest, "scan {all}, grid {nearest}");
}
