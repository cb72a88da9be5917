//! `--record` and `--view` from the command line: what `keylo run` and `keylo localise` record,
//! and clear errors for bad options (the live stream's own test, with an independent client,
//! is scripts/view/live-test.sh; the recording read by PyPI's `mcap` is
//! crates/keylo-py/tests/test_recording.py).

mod common;

use std::collections::BTreeMap;

use common::{expect_failure, keylo_line, small_sim, stderr};

/// Message count per topic, and the JSON of every `/keylo/stats` message.
fn read(path: &std::path::Path) -> (BTreeMap<String, u64>, Vec<serde_json::Value>) {
    let bytes = std::fs::read(path).expect("the recording");
    let summary = mcap::Summary::read(&bytes)
        .expect("a readable summary")
        .expect("a summary section");
    let stats = summary.stats.as_ref().expect("statistics");
    let counts = (stats.channel_message_counts.iter())
        .map(|(id, n)| (summary.channels[id].topic.clone(), *n))
        .collect();
    let json = mcap::MessageStream::new(&bytes)
        .expect("messages")
        .filter_map(Result::ok)
        .filter(|m| m.channel.topic == "/keylo/stats")
        .map(|m| serde_json::from_slice(&m.data).expect("JSON stats"))
        .collect();
    (counts, json)
}

#[test]
fn run_and_localise_record_their_streams() {
    let dir = tempfile::tempdir().unwrap();
    small_sim(&dir.path().join("data"), 6);
    let o = keylo_line(
        "run --data data --out run --map-out map --record run.mcap --view-map-every 2 -q",
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (counts, stats) = read(&dir.path().join("run.mcap"));
    for topic in [
        "/keylo/scan",
        "/keylo/pose",
        "/keylo/registered",
        "/keylo/stats",
    ] {
        assert_eq!(counts.get(topic), Some(&6), "{topic}: {counts:?}");
    }
    // Frames 0, 2 and 4, then after the last.
    assert_eq!(counts.get("/keylo/map"), Some(&4), "{counts:?}");
    let frames: Vec<u64> = stats.iter().filter_map(|s| s["frame"].as_u64()).collect();
    assert_eq!(frames, [0, 1, 2, 3, 4, 5]);

    let o = keylo_line(
        "localise map --data data --out loc --record loc.mcap --set localise.voxel_size=0.3",
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (counts, stats) = read(&dir.path().join("loc.mcap"));
    assert_eq!(counts.get("/keylo/pose"), Some(&6), "{counts:?}");
    // The saved map does not change: recorded once, with the first frame.
    assert_eq!(counts.get("/keylo/map"), Some(&1), "{counts:?}");
    assert!(
        stats
            .iter()
            .all(|s| s["tracking"] == true && s["fitness"].as_f64().is_some()),
        "{stats:?}"
    );
}

#[test]
fn bad_view_and_record_options_are_errors_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    small_sim(&dir.path().join("data"), 2);
    let o = keylo_line("run --data data --out a --view nonsense", dir.path());
    expect_failure(&o, 2, "--view nonsense: expected HOST:PORT");
    let o = keylo_line("run --data data --out a --view 127.0.0.1:99999", dir.path());
    expect_failure(&o, 2, "port `99999` is not a number 0..=65535");
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port();
    let o = keylo_line(
        &format!("run --data data --out a --view 127.0.0.1:{port}"),
        dir.path(),
    );
    expect_failure(&o, 2, &format!("--view 127.0.0.1:{port}: "));
    let o = keylo_line(
        "run --data data --out a --record nowhere/run.mcap",
        dir.path(),
    );
    expect_failure(&o, 2, "--record nowhere/run.mcap: cannot create it");
    // A bad option leaves an existing recording as it was.
    std::fs::write(dir.path().join("kept.mcap"), b"an earlier recording").unwrap();
    for bad in ["--view nonsense", "--view-wait -1 --view 127.0.0.1:0"] {
        let o = keylo_line(
            &format!("run --data data --out a --record kept.mcap {bad}"),
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        let kept = std::fs::read(dir.path().join("kept.mcap")).unwrap();
        assert_eq!(kept, b"an earlier recording", "{bad}");
    }
}

#[test]
fn a_run_that_stops_at_a_bad_frame_leaves_a_complete_recording() {
    let dir = tempfile::tempdir().unwrap();
    small_sim(&dir.path().join("data"), 4);
    // Frame 2's file cut short: the run stops there (exit 3) keeping frames 0 and 1.
    let frames = dir.path().join("data/frames");
    let mut files: Vec<_> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let bytes = std::fs::read(&files[2]).unwrap();
    std::fs::write(&files[2], &bytes[..bytes.len() / 2]).unwrap();
    let o = keylo_line("run --data data --out a --record run.mcap", dir.path());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let (counts, stats) = read(&dir.path().join("run.mcap"));
    assert_eq!(counts.get("/keylo/pose"), Some(&2), "{counts:?}");
    assert_eq!(stats.len(), 2);
}

#[test]
fn a_viewer_that_never_comes_does_not_stop_the_run() {
    let dir = tempfile::tempdir().unwrap();
    small_sim(&dir.path().join("data"), 2);
    let o = keylo_line(
        "run --data data --out a --view 127.0.0.1:0 --view-wait 0.3",
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("live view at ws://127.0.0.1:"), "{e}");
    assert!(e.contains("no viewer connected to ws://127.0.0.1:"), "{e}");
}
