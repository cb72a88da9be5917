#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Some(t) = keylo_fuzz::target("ouster_metadata") {
        (t.run)(data);
    }
});
