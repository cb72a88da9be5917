//! `keylo_pipeline_new` refuses a config naming libraries of its own (`[plugins] dirs`,
//! `onnxruntime`); `keylo_pipeline_new_with_flags(…, KEYLO_TRUST_PLUGINS, …)` loads them. The
//! library here leaves a marker file from its load-time constructor, so the marker's absence
//! proves that nothing was loaded.

use std::ffi::{c_char, CStr, CString};
use std::path::Path;

use keylo_capi::ffi::*;

/// Compiles the CLI tests' marker library into `out`.
fn marker_library(out: &Path) {
    let target = env!("KEYLO_TEST_TARGET");
    let compiler = cc::Build::new()
        .cargo_metadata(false)
        .opt_level(1)
        .target(target)
        .host(target)
        .try_get_compiler()
        .expect("a C compiler");
    let source =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../keylo-cli/tests/fixtures/plugins/marker.c");
    let o = compiler
        .to_command()
        .args(["-shared", "-fPIC", "-std=c99", "-Wall", "-Werror"])
        .arg(source)
        .arg("-o")
        .arg(out)
        .output()
        .expect("the compiler runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `keylo_pipeline_new_with_flags` (`keylo_pipeline_new` when `flags` is `None`) of `toml`
/// in `dir`: the handle, or the error text.
fn make(toml: &str, dir: &Path, flags: Option<u32>) -> Result<*mut KeyloPipeline, String> {
    let (toml, base) = (
        CString::new(toml).unwrap(),
        CString::new(dir.to_str().unwrap()).unwrap(),
    );
    let mut err = [0 as c_char; 1024];
    let (t, b, e) = (toml.as_ptr(), base.as_ptr(), err.as_mut_ptr());
    // SAFETY: valid strings and a buffer of the length given.
    let p = unsafe {
        match flags {
            None => keylo_pipeline_new(t, b, e, 1024),
            Some(f) => keylo_pipeline_new_with_flags(t, b, f, e, 1024),
        }
    };
    if p.is_null() {
        // SAFETY: NUL-terminated by keylo.
        Err(unsafe { CStr::from_ptr(err.as_ptr()) }
            .to_string_lossy()
            .into_owned())
    } else {
        Ok(p)
    }
}

#[test]
fn a_configs_own_libraries_load_only_with_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("p")).unwrap();
    marker_library(&dir.path().join("p/libmarker.so"));
    let marker = dir.path().join("marker");
    std::env::set_var("KEYLO_TEST_MARKER", &marker);
    std::env::set_var("KEYLO_PLUGIN_PATH", dir.path().join("installed"));
    let plugin = "[plugins]\ndirs = [\"p\"]\n[detector]\nkind = \"plugin:marker\"\n";
    let runtime = "[detector]\nkind = \"superpoint\"\nonnxruntime = \"p/libmarker.so\"\n";
    for (toml, named) in [
        (plugin, "libmarker.so ([plugins] dirs)"),
        (runtime, "libmarker.so (detector.onnxruntime)"),
    ] {
        // The plain constructor is the untrusted one, as are flags 0.
        for flags in [None, Some(0)] {
            let e = make(toml, dir.path(), flags).expect_err("refused");
            assert!(e.contains(named), "{e}");
            assert!(e.contains("KEYLO_TRUST_PLUGINS"), "{e}");
            assert!(!marker.exists(), "the library's code ran: {e}");
        }
    }
    // Unknown flag bits are refused, before anything is loaded.
    let e = make(plugin, dir.path(), Some(0x10)).expect_err("refused");
    assert!(e.contains("unknown bits"), "{e}");
    assert!(!marker.exists());
    // Trusted: loaded (then refused as no plugin: it has no entry symbol).
    let e = make(plugin, dir.path(), Some(KEYLO_TRUST_PLUGINS)).expect_err("not a plugin");
    assert!(e.contains("keylo_plugin_entry"), "{e}");
    assert!(marker.exists());
}
