//! Bad Ouster input: each case is a clear error naming the file and what was expected, frames
//! before a corruption stay readable, and nothing panics.

use std::path::{Path, PathBuf};

use keylo_core::{BuildContext, ImageSource};
use keylo_io::ouster::{OusterSource, OusterSourceConfig};

const SAMPLE: &str = "OS-0-128_v3.0.1_1024x10_from_osf";

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/ouster")
}

/// A copy of the sample (pcap bytes and metadata text edited by the closures) in a tempdir.
fn sample(
    pcap: impl FnOnce(Vec<u8>) -> Vec<u8>,
    meta: impl FnOnce(String) -> String,
) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(fixtures().join(format!("{SAMPLE}.pcap"))).unwrap();
    let text = std::fs::read_to_string(fixtures().join(format!("{SAMPLE}.json"))).unwrap();
    let path = dir.path().join("x.pcap");
    std::fs::write(&path, pcap(bytes)).unwrap();
    std::fs::write(dir.path().join("x.json"), meta(text)).unwrap();
    (dir, path)
}

fn open(path: &Path, edit: impl FnOnce(&mut OusterSourceConfig)) -> Result<OusterSource, String> {
    let mut c = OusterSourceConfig {
        path: path.display().to_string(),
        ..OusterSourceConfig::default()
    };
    edit(&mut c);
    let ctx = BuildContext {
        base_dir: PathBuf::from("."),
        ..Default::default()
    };
    OusterSource::open(&c, &ctx).map_err(|e| e.to_string())
}

fn assert_mentions(err: &str, words: &[&str]) {
    for w in words {
        assert!(err.contains(w), "error lacks `{w}`: {err}");
    }
}

#[test]
fn a_truncated_capture_keeps_the_frames_before_the_cut() {
    let (_d, path) = sample(|b| b[..b.len() * 7 / 10].to_vec(), |m| m);
    let mut source = open(&path, |_| {}).unwrap();
    let first = source.next_frame().unwrap().unwrap();
    assert!(first.valid_count() > 30_000);
    let err = source.next_frame().unwrap().unwrap_err().to_string();
    assert_mentions(&err, &["x.pcap", "after 1 frames", "truncated"]);
    assert!(source.next_frame().is_none());
}

#[test]
fn another_link_type_is_refused() {
    let (_d, path) = sample(
        |mut b| {
            b[20] = 101; // LINKTYPE_RAW (little-endian pcap header)
            b
        },
        |m| m,
    );
    assert_mentions(
        &open(&path, |_| {}).err().unwrap(),
        &["x.pcap", "link type", "Ethernet"],
    );
}

#[test]
fn not_a_pcap_is_refused() {
    let (_d, path) = sample(|_| b"hello, not a capture".to_vec(), |m| m);
    assert_mentions(
        &open(&path, |_| {}).err().unwrap(),
        &["x.pcap", "not a pcap"],
    );
}

#[test]
fn packets_to_another_port_are_not_taken() {
    let (_d, path) = sample(|b| b, |m| m);
    let err = open(&path, |c| c.udp_port = 9999).err().unwrap();
    assert_mentions(&err, &["x.pcap", "port 9999", "datagrams to other ports"]);
}

#[test]
fn packets_of_another_sensor_are_not_taken() {
    let (_d, path) = sample(|b| b, |m| m.replace("122247000785", "122247000999"));
    let err = open(&path, |_| {}).err().unwrap();
    assert_mentions(&err, &["x.pcap", "serial 122247000999", "of other sensors"]);
}

#[test]
fn metadata_missing_a_field_names_it() {
    let (_d, path) = sample(
        |b| b,
        |m| m.replace("\"beam_altitude_angles\"", "\"renamed\""),
    );
    let err = open(&path, |_| {}).err().unwrap();
    assert_mentions(&err, &["x.json", "beam_altitude_angles"]);
}

#[test]
fn metadata_of_another_lidar_mode_is_caught() {
    for (cols, last) in [("512", "511"), ("2048", "2047")] {
        let (_d, path) = sample(
            |b| b,
            |m| {
                m.replace(
                    "\"columns_per_frame\":1024",
                    &format!("\"columns_per_frame\":{cols}"),
                )
                .replace("\"1024x10\"", &format!("\"{cols}x10\""))
                .replace(
                    "\"column_window\":[0,1023]",
                    &format!("\"column_window\":[0,{last}]"),
                )
            },
        );
        let mut source = open(&path, |c| {
            c.partial_frames = keylo_io::ouster::PartialFrames::Keep
        })
        .unwrap();
        let err = source.next_frame().unwrap().unwrap_err().to_string();
        assert_mentions(&err, &["x.pcap", "another lidar mode", cols]);
    }
}

#[test]
fn an_unknown_profile_is_named() {
    let (_d, path) = sample(
        |b| b,
        |m| {
            m.replace(
                "\"RNG19_RFL8_SIG16_NIR16\"",
                "\"FUSA_RNG15_RFL8_NIR8_DUAL\"",
            )
        },
    );
    let err = open(&path, |_| {}).err().unwrap();
    assert_mentions(
        &err,
        &["x.pcap", "FUSA_RNG15_RFL8_NIR8_DUAL", "not supported"],
    );
}

#[test]
fn missing_metadata_says_where_it_was_looked_for() {
    let (d, path) = sample(|b| b, |m| m);
    std::fs::remove_file(d.path().join("x.json")).unwrap();
    assert_mentions(&open(&path, |_| {}).err().unwrap(), &["x.json", "--meta"]);
    let other = d.path().join("other.json");
    std::fs::write(&other, "{}").unwrap();
    let err = open(&path, |c| c.meta = other.display().to_string())
        .err()
        .unwrap();
    assert_mentions(&err, &["other.json"]);
}

#[test]
fn bad_rate_control_and_return_number_are_named() {
    let (_d, path) = sample(|b| b, |m| m);
    assert_mentions(&open(&path, |c| c.stride = 0).err().unwrap(), &["stride"]);
    assert_mentions(
        &open(&path, |c| c.return_number = 2).err().unwrap(),
        &["one return"],
    );
    assert_mentions(
        &open(&path, |c| c.return_number = 3).err().unwrap(),
        &["return_number"],
    );
}

#[test]
fn partial_frames_and_rate_control() {
    let (_d, path) = sample(|b| b, |m| m);
    let count = |edit: fn(&mut OusterSourceConfig)| {
        let mut s = open(&path, edit).unwrap();
        std::iter::from_fn(|| s.next_frame())
            .map(|f| f.unwrap().index)
            .collect::<Vec<_>>()
    };
    assert_eq!(count(|_| {}), vec![0, 1]);
    assert_eq!(
        count(|c| c.partial_frames = keylo_io::ouster::PartialFrames::Keep),
        vec![0, 1, 2]
    );
    assert_eq!(
        count(|c| c.partial_frames = keylo_io::ouster::PartialFrames::SkipAll),
        vec![0, 1]
    );
    assert_eq!(count(|c| c.start = 1), vec![1]);
    assert_eq!(count(|c| c.max_frames = 1), vec![0]);
    assert_eq!(
        count(|c| {
            c.partial_frames = keylo_io::ouster::PartialFrames::Keep;
            c.stride = 2;
        }),
        vec![0, 2]
    );
}

/// An azimuth window across the frame's start (ouster-sdk's wrapped column window, e.g.
/// `[1000, 23]`) is valid: its frames are complete when columns 1000..1023 and 0..23 came, and
/// lost packets are counted in both of its parts.
#[test]
fn a_column_window_across_the_frame_start_is_read() {
    let frames_and_lost = |window: &str, partial| {
        let (_d, path) = sample(|b| b, |m| m.replace("\"column_window\":[0,1023]", window));
        let mut s = open(&path, |c| c.partial_frames = partial).unwrap();
        let frames: Vec<u64> = std::iter::from_fn(|| s.next_frame())
            .map(|f| f.unwrap().index)
            .collect();
        let lost = s
            .counters()
            .into_iter()
            .find(|(k, _)| k == "packets_lost")
            .map(|(_, v)| v);
        (frames, lost)
    };
    use keylo_io::ouster::PartialFrames::{Keep, SkipAll};
    let wrapped = "\"column_window\":[1000,23]";
    assert_eq!(
        frames_and_lost(wrapped, SkipAll),
        (vec![0, 1], Some(0)),
        "the two whole turns are complete frames in a wrapped window"
    );
    // The capture's last frame stops after column 383: of the whole window it misses 640
    // columns (40 packets of 16), of the wrapped one columns 1000..=1023 only (2 packets).
    let (all, lost_all) = frames_and_lost("\"column_window\":[0,1023]", Keep);
    let (wrapped_frames, lost_wrapped) = frames_and_lost(wrapped, Keep);
    assert_eq!((all, wrapped_frames), (vec![0, 1, 2], vec![0, 1, 2]));
    assert_eq!((lost_all, lost_wrapped), (Some(40), Some(2)));
}
