// The target triple, for the plugin tests that compile C with the `cc` crate.
fn main() {
    let target = std::env::var("TARGET").unwrap_or_default();
    println!("cargo:rustc-env=KEYLO_TEST_TARGET={target}");
}
