//! The examples in `examples/` run (each is included as a module and its `run` called).

#[path = "../examples/read_pcap.rs"]
mod read_pcap;

#[path = "../examples/embed.rs"]
mod embed;

#[path = "../examples/custom_registrar.rs"]
mod custom_registrar;

#[test]
fn read_pcap_reads_every_frame_of_a_capture() {
    let pcap = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/ouster/OS-0-32-U1_v2.2.0_1024x10.pcap");
    let lines = read_pcap::run(&pcap).unwrap();
    assert!(!lines.is_empty());
    assert!(lines[0].starts_with("frame 0 at"), "{lines:?}");
    assert!(lines[0].contains("32 x 1024"), "{lines:?}");
}

#[test]
fn embed_tracks_a_sensor_moving_through_a_room() {
    let poses = embed::run(10).unwrap();
    let x = poses[9].translation.x;
    assert!((x - 0.9).abs() < 0.05, "moved {x} m, expected 0.9 m");
}

#[test]
fn a_user_registrar_runs_in_the_pipeline() {
    let xs = custom_registrar::run("[registrar]\nkind = \"centroid\"\n").unwrap();
    for (k, x) in xs.iter().enumerate() {
        assert!((x - 0.5 * k as f64).abs() < 1e-9, "{xs:?}");
    }
    // Its parameters are checked like a built-in backend's.
    let e = custom_registrar::run("[registrar]\nkind = \"centroid\"\ngains = 2\n")
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("gains"), "{e}");
    // From its typed config: gain 2 doubles every step.
    let xs = custom_registrar::run_typed(2.0).unwrap();
    assert!((xs[4] - 4.0).abs() < 1e-9, "{xs:?}");
}
