//! Pictures and reports: `keylo run --images` draws keypoints where a detector put them (a C
//! plugin with keypoints on a known lattice) and tints the pixels the downsampler kept;
//! `keylo report` makes one self-contained page of a run or a compare folder; the page
//! loads in headless Chromium without errors and its 3-D views draw.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{compile_plugin, root, small_sim, stderr, stdout};

/// Overlay colours (crates/keylo-cli/src/overlay/image_view.rs).
const CENTRE: [u8; 3] = [255, 40, 40];
const OUTLINE: [u8; 3] = [255, 210, 0];

const CONFIG: &str = r#"
[image]
kind = "lidar"
images = ["signal"]

[detector]
kind = "plugin:lattice"

[downsampler]
kind = "keypoint-neighbourhood"
windows = { signal = 5 }

[registrar]
kind = "kiss-icp"
voxel_size = 0.2
"#;

/// A temp folder with `plugins/liblattice.so`, `data/` (six simulated frames with gt.tum)
/// and `lattice.toml`.
struct Setup {
    dir: tempfile::TempDir,
}

impl Setup {
    fn new() -> Self {
        let dir = tempfile::tempdir().expect("temp dir");
        let plugins = dir.path().join("plugins");
        std::fs::create_dir_all(&plugins).expect("plugins folder");
        let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/plugins/lattice.c");
        compile_plugin(&source, &plugins.join("liblattice.so"), &[]);
        small_sim(&dir.path().join("data"), 6);
        std::fs::write(dir.path().join("lattice.toml"), CONFIG).expect("config");
        Self { dir }
    }

    fn path(&self, rel: &str) -> PathBuf {
        self.dir.path().join(rel)
    }

    fn keylo(&self, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_keylo"))
            .args(args)
            .current_dir(self.dir.path())
            .env("KEYLO_PLUGIN_PATH", self.path("plugins"))
            .output()
            .expect("the keylo binary runs")
    }

    /// `keylo run lattice.toml --data data --out OUT --images 2`.
    fn run(&self, out: &str) -> PathBuf {
        let o = self.keylo(&[
            "run",
            "lattice.toml",
            "--data",
            "data",
            "--out",
            out,
            "--images",
            "2",
            "-q",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        self.path(out)
    }
}

/// Width, height and RGB bytes of a PNG.
fn read_png(path: &Path) -> (usize, usize, Vec<u8>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("PNG frame");
    let channels = info.color_type.samples();
    let rgb = buf[..info.buffer_size()]
        .chunks(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width as usize, info.height as usize, rgb)
}

fn pixel(img: &(usize, usize, Vec<u8>), x: usize, y: usize) -> [u8; 3] {
    let i = 3 * (y * img.0 + x);
    [img.2[i], img.2[i + 1], img.2[i + 2]]
}

#[test]
fn pictures_show_keypoints_where_the_detector_put_them_and_the_kept_windows() {
    let s = Setup::new();
    let out = s.run("out");
    let index: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("images/pictures.json")).expect("pictures.json"),
    )
    .expect("JSON");
    let frames: Vec<u64> = index
        .as_array()
        .expect("a list")
        .iter()
        .map(|p| p["frame"].as_u64().expect("frame"))
        .collect();
    assert_eq!(frames, [0, 2, 4]);
    assert_eq!(index[0]["clouds"][0], "frame_000000_raw.ply");
    assert!(index[1]["clouds"].is_null());
    let img = read_png(&out.join("images/frame_000000_signal.png"));
    // A 64-row image is drawn twice as large: image point (x, y) is canvas (2x + 1, 2y + 1).
    let (w, h) = (img.0 / 2, img.1 / 2);
    assert_eq!(h, 64, "image height");
    let mut checked = 0;
    for j in (0..).map(|j| 8 + 16 * j).take_while(|y| *y < h) {
        for (i, x) in (0..)
            .map(|i| 16 + 64 * i)
            .take_while(|x| *x < w)
            .enumerate()
        {
            let (cx, cy) = (2 * x + 1, 2 * j + 1);
            assert_eq!(pixel(&img, cx, cy), CENTRE, "keypoint ({x}, {j})");
            // Size 10 → radius 10 canvas pixels: the circle's top point.
            assert_eq!(pixel(&img, cx, cy - 10), OUTLINE, "circle of ({x}, {j})");
            // Angle 0 (every other keypoint): a line from the centre along +x.
            let oriented = (i + (j - 8) / 16) % 2 == 0;
            assert_eq!(
                pixel(&img, cx + 5, cy) == OUTLINE,
                oriented,
                "orientation of ({x}, {j})"
            );
            checked += 1;
        }
    }
    assert!(checked >= 12, "{checked} keypoints checked");
    // Inside the 5 × 5 window (2 pixels off the keypoint at (16, 8)): tinted blue where kept;
    // half-way between keypoints: untouched grey.
    let tinted = [
        (2 * 18 + 1, 2 * 10 + 1),
        (2 * 14 + 1, 2 * 6 + 1),
        (2 * 18, 2 * 6),
    ]
    .iter()
    .filter(|(x, y)| {
        let p = pixel(&img, *x, *y);
        p[2] > p[0] + 40
    })
    .count();
    assert!(tinted >= 2, "{tinted} of 3 window pixels tinted");
    let p = pixel(&img, 2 * 48, 2 * 16);
    assert!(
        p[0] == p[1] && p[1] == p[2],
        "not grey between windows: {p:?}"
    );
    // The top view shows registered points (orange) among the raw ones.
    let top = read_png(&out.join("images/frame_000000_top.png"));
    let orange = top.2.chunks(3).filter(|p| p == &[255, 130, 0]).count();
    assert!(orange > 50, "{orange} orange pixels in the top view");
    // The same run again gives the same bytes.
    let again = s.run("again");
    for name in [
        "frame_000002_signal.png",
        "frame_000002_top.png",
        "frame_000000_selected.ply",
    ] {
        let a = std::fs::read(out.join("images").join(name)).expect("first");
        let b = std::fs::read(again.join("images").join(name)).expect("second");
        assert!(a == b, "{name} differs between two runs");
    }
}

#[test]
fn report_of_a_run_and_of_a_compare_folder_is_one_self_contained_page() {
    let s = Setup::new();
    let out = s.run("out");
    assert!(out.join("map.ply").is_file() && out.join("reference.tum").is_file());
    let o = s.keylo(&["report", "out", "--max-points", "500"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("2 3-D view(s)"), "{}", stdout(&o));
    let html = std::fs::read_to_string(out.join("report.html")).expect("report.html");
    for needle in [
        "data-scene=\"0\"",
        "data-scene=\"1\"",
        "src=\"data:image/png;base64,",
        "one in ", // the raw frame cloud is thinned to 500 points, and the page says so
        "(aligned as for the accuracy figures)",
        "<svg",
        "OrbitControls",
    ] {
        assert!(html.contains(needle), "report.html lacks {needle}");
    }
    // Self-contained: nothing is fetched from elsewhere.
    for outside in ["src=\"http", "href=\"http", "src=\"/", "import("] {
        assert!(
            !html.contains(outside),
            "report.html refers outside: {outside}"
        );
    }
    let o = s.keylo(&[
        "compare",
        "lattice.toml",
        "--data",
        "data",
        "--out",
        "cmp",
        "--grid",
        "registrar.voxel_size=0.2,0.4",
        "--images",
        "3",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = s.keylo(&["report", "cmp", "--out", "cmp.html"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let html = std::fs::read_to_string(s.path("cmp.html")).expect("cmp.html");
    assert!(
        html.contains("Trajectories on data (3-D)"),
        "no 3-D trajectories"
    );
    assert!(
        html.contains("<table>") && html.contains("<svg"),
        "no tables or plots"
    );
    assert!(
        html.contains("Pictures of "),
        "no pictures of a run made with --images"
    );
    // Not a run or compare folder: a clear error, no page.
    let o = s.keylo(&["report", "data"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("neither a run folder"),
        "{}",
        stderr(&o)
    );
    assert!(!s.path("data/report.html").exists());
}

/// A Chromium (or Chrome) on PATH, or KEYLO_BROWSER.
fn browser() -> Option<PathBuf> {
    if let Some(b) = std::env::var_os("KEYLO_BROWSER") {
        return Some(PathBuf::from(b));
    }
    let path = std::env::var_os("PATH")?;
    [
        "chromium",
        "chromium-browser",
        "google-chrome",
        "google-chrome-stable",
    ]
    .iter()
    .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
    .find(|p| p.is_file())
}

/// Runs the browser headless on `page` with `args`; WebGL through SwiftShader (software).
fn headless(browser: &Path, profile: &Path, page: &Path, args: &[String]) -> Output {
    Command::new("timeout")
        .arg("180")
        .arg(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--hide-scrollbars",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--virtual-time-budget=15000",
            "--window-size=1280,1900",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("the browser starts")
}

/// The value of attribute `name` in the dumped DOM, unescaped.
fn attribute(dom: &str, name: &str) -> Option<String> {
    let start = dom.find(&format!("{name}=\""))? + name.len() + 2;
    let end = start + dom[start..].find('"')?;
    Some(
        dom[start..end]
            .replace("&quot;", "\"")
            .replace("&amp;", "&"),
    )
}

#[test]
fn report_loads_in_headless_chromium_and_its_3d_views_draw() {
    let Some(browser) = browser() else {
        assert!(
            std::env::var_os("KEYLO_REQUIRE_BROWSER").is_none(),
            "KEYLO_REQUIRE_BROWSER is set but no Chromium was found"
        );
        eprintln!(
            "skipped: no Chromium found (install Debian's `chromium`, as scripts/test.sh does, \
             or set KEYLO_BROWSER)"
        );
        return;
    };
    let s = Setup::new();
    let out = s.run("out");
    let o = s.keylo(&["report", "out"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = out.join("report.html");
    let profile = s.path("profile");
    let dom = headless(&browser, &profile, &page, &["--dump-dom".into()]);
    let text = String::from_utf8_lossy(&dom.stdout);
    assert!(dom.status.success(), "browser failed: {}", stderr(&dom));
    assert_eq!(
        attribute(&text, "data-errors").as_deref(),
        Some("[]"),
        "console errors"
    );
    let views: serde_json::Value =
        serde_json::from_str(&attribute(&text, "data-views").expect("data-views set by the page"))
            .expect("JSON");
    let views = views.as_array().expect("a list");
    assert_eq!(views.len(), 2, "{views:?}");
    for v in views {
        assert!(
            v["drawn"].as_u64().unwrap_or(0) > 100,
            "a blank 3-D view: {v}"
        );
    }
    assert!(!stderr(&dom).contains("Uncaught"), "{}", stderr(&dom));
    // The screenshot: the first 3-D view (background #141414) holds drawn pixels.
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-screenshot.png");
    let o = headless(
        &browser,
        &profile,
        &page,
        &[format!("--screenshot={}", shot.display())],
    );
    assert!(
        o.status.success() && shot.is_file(),
        "no screenshot: {}",
        stderr(&o)
    );
    let img = read_png(&shot);
    let bg: Vec<(usize, usize)> = (0..img.1)
        .flat_map(|y| (0..img.0).map(move |x| (x, y)))
        .filter(|&(x, y)| pixel(&img, x, y) == [20, 20, 20])
        .collect();
    assert!(bg.len() > 100_000, "no 3-D view on the screenshot");
    let (x0, x1) = (
        bg.iter().map(|p| p.0).min().unwrap_or(0),
        bg.iter().map(|p| p.0).max().unwrap_or(0),
    );
    let (y0, y1) = (
        bg.iter().map(|p| p.1).min().unwrap_or(0),
        bg.iter().map(|p| p.1).max().unwrap_or(0),
    );
    let drawn = (y0..=y1)
        .flat_map(|y| (x0..=x1).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = pixel(&img, x, y);
            p.iter().map(|&c| (i32::from(c) - 20).abs()).sum::<i32>() > 60
        })
        .count();
    assert!(
        drawn > 200,
        "{drawn} drawn pixels in the 3-D views of the screenshot"
    );
    eprintln!("screenshot kept: {}", shot.display());
    let _ = root();
}

#[test]
fn a_report_notes_what_it_cannot_read_and_is_still_written() {
    let s = Setup::new();
    let out = s.run("out");
    // A run stopped before its first frame leaves an empty trajectory; a picture is gone; the
    // map is damaged; pictures.json points outside its folder.
    std::fs::write(out.join("trajectory.tum"), "").expect("truncate");
    std::fs::remove_file(out.join("images/frame_000002_top.png")).expect("remove");
    std::fs::write(out.join("map.ply"), "ply\nformat nonsense\n").expect("damage");
    let index = out.join("images/pictures.json");
    let text = std::fs::read_to_string(&index).expect("pictures.json");
    std::fs::write(
        &index,
        text.replace("frame_000004_top.png", "../../data/gt.tum"),
    )
    .expect("rewrite");
    let o = s.keylo(&["report", "out"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let html = std::fs::read_to_string(out.join("report.html")).expect("report.html");
    for needle in [
        "trajectory.tum",
        "frame_000002_top.png",
        "map.ply",
        "is not a file name in images/",
    ] {
        let noted = html
            .split("<p class=\"warn\">Not shown: ")
            .skip(1)
            .any(|n| n.split("</p>").next().is_some_and(|n| n.contains(needle)));
        assert!(noted, "no note about {needle}");
    }
}
