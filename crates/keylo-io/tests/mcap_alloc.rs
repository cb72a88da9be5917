//! MCAP files whose record or chunk lengths claim far more bytes than the file holds must give
//! an error (or frames) quickly and without allocating what they claim: every buffer is bounded
//! by the bytes the input can supply. A counting global allocator measures the largest single
//! allocation and the peak of live heap bytes while each file is listed and read (its own test
//! binary, one test, so no other test allocates meanwhile). Allocations inside libzstd and
//! liblz4 (C) are not counted.
//!
//! The same files are fuzz regression inputs (`fuzz/regressions/mcap/`), written by
//! `cargo test -p keylo-io --test mcap_alloc -- --ignored write_fuzz_regressions`.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::time::{Duration, Instant};

use keylo_core::{BuildContext, ImageSource};
use keylo_io::ros::{bag_info, BagFormat, BagSource, BagSourceConfig};

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static LARGEST: AtomicUsize = AtomicUsize::new(0);

fn allocated(size: usize) {
    let live = LIVE.fetch_add(size, Relaxed) + size;
    PEAK.fetch_max(live, Relaxed);
    LARGEST.fetch_max(size, Relaxed);
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            allocated(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            allocated(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        LIVE.fetch_sub(layout.size(), Relaxed);
    }
    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, layout, new_size) };
        if !q.is_null() {
            LIVE.fetch_sub(layout.size(), Relaxed);
            allocated(new_size);
        }
        q
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// What a claimed length is set to: 400 MiB, under keylo's 512 MiB record limit.
const HUGE: u64 = 400 << 20;

/// What a string inside a record claims: 3 GiB (its length is a u32).
const HUGE_STRING: u32 = 3 << 30;

// ---- MCAP records (https://mcap.dev/spec), little-endian ----

fn record(opcode: u8, body: &[u8]) -> Vec<u8> {
    record_claiming(opcode, body.len() as u64, body)
}

/// A record whose length field says `len`, followed by `body` (which may be shorter).
fn record_claiming(opcode: u8, len: u64, body: &[u8]) -> Vec<u8> {
    let mut out = vec![opcode];
    out.extend(len.to_le_bytes());
    out.extend(body);
    out
}

fn string(s: &str) -> Vec<u8> {
    let mut out = (s.len() as u32).to_le_bytes().to_vec();
    out.extend(s.as_bytes());
    out
}

fn header() -> Vec<u8> {
    record(0x01, &[string(""), string("keylo-test")].concat())
}

fn schema() -> Vec<u8> {
    let data = b"# a PointCloud2 definition would go here";
    let mut body = 1u16.to_le_bytes().to_vec();
    body.extend(string("sensor_msgs/msg/PointCloud2"));
    body.extend(string("ros2msg"));
    body.extend((data.len() as u32).to_le_bytes());
    body.extend(data);
    record(0x03, &body)
}

fn channel() -> Vec<u8> {
    channel_claiming(None)
}

/// Channel 1 on `/points`; `claim` overrides the topic's length field (the record's own length
/// stays right).
fn channel_claiming(claim: Option<u32>) -> Vec<u8> {
    let mut body = [1u16.to_le_bytes(), 1u16.to_le_bytes()].concat();
    let topic = "/points";
    body.extend(claim.unwrap_or(topic.len() as u32).to_le_bytes());
    body.extend(topic.as_bytes());
    body.extend(string("cdr"));
    body.extend(0u32.to_le_bytes()); // empty metadata map
    record(0x04, &body)
}

/// A message on channel 1 at `t` ns; `claim` overrides its length field.
fn message(t: u64, data: &[u8], claim: Option<u64>) -> Vec<u8> {
    let mut body = 1u16.to_le_bytes().to_vec();
    body.extend(0u32.to_le_bytes());
    body.extend(t.to_le_bytes());
    body.extend(t.to_le_bytes());
    body.extend(data);
    record_claiming(0x05, claim.unwrap_or(body.len() as u64), &body)
}

/// A chunk of `records` compressed with `compression` ("", "zstd", "lz4"); `claim` overrides
/// the declared uncompressed size.
fn chunk(records: &[u8], compression: &str, claim: Option<u64>) -> Vec<u8> {
    let data = match compression {
        "" => records.to_vec(),
        "zstd" => zstd::encode_all(records, 3).unwrap(),
        "lz4" => {
            let mut e = lz4::EncoderBuilder::new().build(Vec::new()).unwrap();
            std::io::Write::write_all(&mut e, records).unwrap();
            let (out, r) = e.finish();
            r.unwrap();
            out
        }
        other => panic!("{other}"),
    };
    let mut body = [0u64.to_le_bytes(), 100u64.to_le_bytes()].concat();
    body.extend(claim.unwrap_or(records.len() as u64).to_le_bytes());
    body.extend(crc32fast::hash(records).to_le_bytes());
    body.extend(string(compression));
    body.extend((data.len() as u64).to_le_bytes());
    body.extend(data);
    record(0x06, &body)
}

fn chunk_index(pos: u64, chunk: &[u8]) -> Vec<u8> {
    // The chunk record's own header: start, end, uncompressed size, CRC, compression, size.
    let h = &chunk[9..];
    let clen = u32::from_le_bytes(h[28..32].try_into().unwrap()) as usize;
    let compression = &h[32..32 + clen];
    let compressed = &h[32 + clen..40 + clen];
    let mut body = [0u64.to_le_bytes(), 100u64.to_le_bytes()].concat();
    body.extend(pos.to_le_bytes());
    body.extend((chunk.len() as u64).to_le_bytes());
    body.extend(0u32.to_le_bytes()); // message index offsets: none
    body.extend(0u64.to_le_bytes()); // message index length
    body.extend((clen as u32).to_le_bytes());
    body.extend(compression);
    body.extend(compressed);
    body.extend(&h[16..24]); // uncompressed size
    record(0x08, &body)
}

/// One message on channel 1, at 5 ns, in one chunk.
fn statistics() -> Vec<u8> {
    let mut body = 1u64.to_le_bytes().to_vec();
    body.extend(1u16.to_le_bytes());
    body.extend([1u32, 0, 0, 1].map(u32::to_le_bytes).concat());
    body.extend([5u64, 5].map(u64::to_le_bytes).concat());
    body.extend(10u32.to_le_bytes());
    body.extend(1u16.to_le_bytes());
    body.extend(1u64.to_le_bytes());
    record(0x0B, &body)
}

fn footer(summary_start: u64) -> Vec<u8> {
    let mut body = summary_start.to_le_bytes().to_vec();
    body.extend(0u64.to_le_bytes());
    body.extend(0u32.to_le_bytes());
    record(0x02, &body)
}

/// A whole file: schema and channel, then `chunk`, then (when `summary`) a summary with the
/// chunk's index, so it is read indexed; without, it is read in file order.
fn file(chunk: &[u8], summary: bool) -> Vec<u8> {
    file_with(&channel(), chunk, summary.then(channel))
}

/// As [`file`], with the channel records given: `data` before the chunk, `summary` (when
/// `Some`) in the summary.
fn file_with(data: &[u8], chunk: &[u8], summary: Option<Vec<u8>>) -> Vec<u8> {
    let mut out = mcap::MAGIC.to_vec();
    out.extend(header());
    out.extend(schema());
    out.extend(data);
    let pos = out.len() as u64;
    out.extend(chunk);
    out.extend(record(0x0F, &0u32.to_le_bytes()));
    let summary_start = if summary.is_some() {
        out.len() as u64
    } else {
        0
    };
    if let Some(channel) = summary {
        out.extend(schema());
        out.extend(channel);
        out.extend(chunk_index(pos, chunk));
        out.extend(statistics());
    }
    out.extend(footer(summary_start));
    out.extend(mcap::MAGIC);
    out
}

fn cloud_message() -> Vec<u8> {
    message(5, &[0u8; 64], None)
}

/// The damaged files, by name, with words their error must contain.
fn cases() -> Vec<(&'static str, Vec<u8>, Vec<String>)> {
    let claims = format!("declares {HUGE}");
    let msgs = cloud_message();
    // Schema and channel first, so that only the claimed length is wrong.
    let mut start = mcap::MAGIC.to_vec();
    start.extend(header());
    start.extend(schema());
    start.extend(channel());
    let at = start.len();
    let top = [start.clone(), record_claiming(0x03, HUGE, b"short")].concat();
    let chunk_body = &chunk(&msgs, "zstd", None)[9..];
    let top_chunk = [start, record_claiming(0x06, HUGE, chunk_body)].concat();
    let in_chunk = message(5, &[0u8; 64], Some(HUGE));
    let big = Some(HUGE);
    let bad_channel = channel_claiming(Some(HUGE_STRING));
    let topic = "`topic` (byte 4 of the record) declares 3221225472 bytes";
    let channel_at = at - channel().len();
    let mut bad_compression = chunk(&msgs, "zstd", None);
    // opcode, length, start, end, uncompressed size, CRC: the compression string's length.
    bad_compression[37..41].copy_from_slice(&HUGE_STRING.to_le_bytes());
    let words = |w: &[&str]| {
        w.iter()
            .map(|w| w.to_string())
            .chain([claims.clone()])
            .collect()
    };
    let in_chunk_words = words(&["chunk at byte", "record at byte 0 of the chunk's records"]);
    vec![
        (
            "huge_record_length",
            top,
            words(&[&format!("record at byte {at} (opcode 0x03)")]),
        ),
        (
            "huge_chunk_length",
            top_chunk,
            words(&[&format!("record at byte {at} (opcode 0x06)")]),
        ),
        (
            "huge_uncompressed_size_indexed",
            file(&chunk(&msgs, "zstd", big), true),
            words(&["chunk at byte"]),
        ),
        (
            "huge_uncompressed_size",
            file(&chunk(&msgs, "zstd", big), false),
            words(&["chunk at byte"]),
        ),
        (
            "huge_uncompressed_size_lz4",
            file(&chunk(&msgs, "lz4", big), false),
            words(&["chunk at byte"]),
        ),
        (
            "huge_record_in_chunk_indexed",
            file(&chunk(&in_chunk, "zstd", None), true),
            in_chunk_words.clone(),
        ),
        (
            "huge_record_in_chunk",
            file(&chunk(&in_chunk, "zstd", None), false),
            in_chunk_words.clone(),
        ),
        (
            "huge_record_in_plain_chunk",
            file(&chunk(&in_chunk, "", None), false),
            in_chunk_words,
        ),
        (
            "huge_string",
            file_with(&bad_channel, &chunk(&msgs, "zstd", None), None),
            vec![format!(
                "record at byte {channel_at} (opcode 0x04): {topic}"
            )],
        ),
        (
            // The summary is refused and the file read in file order instead.
            "huge_string_in_summary",
            file_with(
                &channel(),
                &chunk(&msgs, "zstd", None),
                Some(bad_channel.clone()),
            ),
            vec!["summary unreadable".to_string(), topic.to_string()],
        ),
        (
            "huge_string_in_chunk",
            file_with(
                &[],
                &chunk(&[bad_channel, msgs].concat(), "zstd", None),
                None,
            ),
            vec![format!("record at byte 0 of its records: {topic}")],
        ),
        (
            "huge_compression_string",
            file(&bad_compression, false),
            vec![format!(
                "chunk at byte {at}: `compression` (byte 28 of the record) declares 3221225472"
            )],
        ),
    ]
}

/// Lists `path` as `keylo info` does and reads it as source kind `mcap`: the notes and errors
/// of the listing (note, damage, first-message errors) and the source's error (at open, or of
/// the first failing frame).
fn list_and_read(path: &Path) -> (String, String) {
    let mut listing = String::new();
    match bag_info(path) {
        Ok(info) => {
            listing.extend(info.note);
            listing.extend(info.damage);
            for t in info.topics {
                listing.extend(t.cloud_error);
            }
        }
        Err(e) => listing.push_str(&e.to_string()),
    }
    let config = BagSourceConfig {
        path: path.display().to_string(),
        ..BagSourceConfig::default()
    };
    let ctx = BuildContext {
        base_dir: ".".into(),
        ..Default::default()
    };
    let source = match BagSource::open(&config, &ctx, BagFormat::Mcap) {
        Ok(mut source) => std::iter::from_fn(|| source.next_frame())
            .find_map(Result::err)
            .map(|e| e.to_string())
            .unwrap_or_default(),
        Err(e) => e.to_string(),
    };
    (listing, source)
}

#[test]
fn claimed_lengths_allocate_only_what_the_file_holds() {
    // The builders are right: the intact file lists one cloud message, read indexed and not.
    let dir = tempfile::tempdir().unwrap();
    for summary in [true, false] {
        let path = dir.path().join("ok.mcap");
        std::fs::write(&path, file(&chunk(&cloud_message(), "zstd", None), summary)).unwrap();
        let info = bag_info(&path).unwrap();
        assert_eq!(info.damage, None);
        assert_eq!(info.topics.len(), 1);
        assert_eq!(info.topics[0].count, Some(1), "{info:?}");
        let (listing, source) = list_and_read(&path);
        assert!(!listing.contains("chunk at byte"), "{listing}");
        assert!(!source.contains("chunk at byte"), "{source}");
    }
    let mut failures = Vec::new();
    for (name, bytes, words) in cases() {
        let path = dir.path().join(format!("{name}.mcap"));
        std::fs::write(&path, &bytes).unwrap();
        let live = LIVE.load(Relaxed);
        PEAK.store(live, Relaxed);
        LARGEST.store(0, Relaxed);
        let t0 = Instant::now();
        let (listing, source) = list_and_read(&path);
        let took = t0.elapsed();
        let (peak, largest) = (PEAK.load(Relaxed) - live, LARGEST.load(Relaxed));
        eprintln!(
            "{name} ({} bytes): largest allocation {largest} B, peak heap growth {peak} B, \
             {took:?}\n  listing: {listing}\n  source: {source}",
            bytes.len()
        );
        // The errors say where the damage is and what it claims; the source's names the file.
        let file_name = format!("{name}.mcap");
        if !source.contains(&file_name) {
            failures.push(format!(
                "{name}: the file's name is not in the source's error"
            ));
        }
        for w in words {
            if !source.contains(&w) && !listing.contains(&w) {
                failures.push(format!("{name}: `{w}` is in no error"));
            }
        }
        if largest >= 1 << 20 {
            failures.push(format!("{name}: an allocation of {largest} bytes"));
        }
        if peak >= 4 << 20 {
            failures.push(format!("{name}: the heap grew by {peak} bytes"));
        }
        if took >= Duration::from_secs(2) {
            failures.push(format!("{name}: took {took:?}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Writes the damaged files to `fuzz/regressions/mcap/` (run by hand, see the module doc).
#[test]
#[ignore]
fn write_fuzz_regressions() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/regressions/mcap");
    for (name, bytes, _) in cases() {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
}
