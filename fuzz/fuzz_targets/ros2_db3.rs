#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Some(t) = keylo_fuzz::target("ros2_db3") {
        (t.run)(data);
    }
});
