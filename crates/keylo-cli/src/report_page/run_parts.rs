//! What a report shows of one run folder (`keylo run --out DIR`): its summary and the local
//! map with the trajectory and the reference (pictures: `pictures_part`). A file that cannot
//! be read becomes a note on the page, never a missing page.

use std::path::Path;

use anyhow::{Context, Result};
use serde_json::Value;

use super::html::{self, escape};
use super::scene::{Cloud, Polyline, Scene};

/// Colours shared by every report.
pub const MAP: &str = "#9a9a9a";
pub const ESTIMATE: &str = "#ff8c1a";
pub const REFERENCE: &str = "#3ddc84";
pub const SELECTED: &str = "#ff8200";

/// Limits on what goes into the page.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Points per 3-D layer.
    pub max_points: usize,
    /// Pictured frames.
    pub max_pictures: usize,
}

/// What could not be shown, and why (each an error chain).
pub type Notes = Vec<String>;

/// `r`'s value, or `None` with its error noted.
pub fn soft<T>(r: Result<T>, notes: &mut Notes) -> Option<T> {
    r.map_err(|e| notes.push(format!("{e:#}"))).ok()
}

/// The notes as warnings on the page (empty when there are none).
pub fn notes_html(notes: &[String]) -> String {
    notes
        .iter()
        .map(|n| format!("<p class=\"warn\">Not shown: {}</p>", escape(n)))
        .collect()
}

/// The headline figures of a run, in this order, where `summary.json` has them.
const HEADLINE: [(&str, &str); 14] = [
    ("frames", "frames"),
    ("odometry_hz", "odometry Hz"),
    ("wall_hz", "end-to-end Hz"),
    ("mean_keypoints", "keypoints"),
    ("mean_cloud_points", "points to registrar"),
    ("mean_registered_points", "points registered"),
    ("peak_rss_mb", "peak RSS MB"),
    ("cpu_percent", "CPU %"),
    ("path_length_m", "path m"),
    ("accuracy.associated_poses", "poses with reference"),
    ("accuracy.ate_rmse_m", "ATE RMSE m"),
    ("accuracy.rpe_trans_rmse_m", "RPE m"),
    ("accuracy.rpe_rot_rmse_deg", "RPE deg"),
    ("accuracy.drift_pct", "drift %"),
];

/// The run's `summary.json`: its headline figures as one table, and every figure
/// (flattened `key: value` rows) for a collapsed details element.
pub fn summary_tables(dir: &Path) -> Result<(Value, String, String)> {
    let path = dir.join("summary.json");
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let summary: Value =
        serde_json::from_str(&text).with_context(|| format!("{}: not JSON", path.display()))?;
    let mut rows = Vec::new();
    flatten("", &summary, &mut rows);
    let (header, values): (Vec<&str>, Vec<String>) = HEADLINE
        .iter()
        .filter_map(|(key, label)| {
            let row = rows.iter().find(|r| r[0] == *key)?;
            Some((*label, row[1].clone()))
        })
        .unzip();
    let headline = html::table(&header, &[values]);
    Ok((summary, headline, html::table(&["figure", "value"], &rows)))
}

fn flatten(prefix: &str, v: &Value, rows: &mut Vec<Vec<String>>) {
    match v {
        Value::Object(map) => {
            for (k, v) in map {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&key, v, rows);
            }
        }
        Value::Null => rows.push(vec![prefix.into(), "—".into()]),
        Value::Number(n) => rows.push(vec![prefix.into(), number(n)]),
        Value::String(s) => rows.push(vec![prefix.into(), s.clone()]),
        Value::Array(items) => {
            let shown: Vec<String> = items
                .iter()
                .map(|v| match v {
                    Value::Number(n) => number(n),
                    other => other.to_string(),
                })
                .collect();
            rows.push(vec![prefix.into(), shown.join(", ")]);
        }
        Value::Bool(b) => rows.push(vec![prefix.into(), b.to_string()]),
    }
}

fn number(n: &serde_json::Number) -> String {
    match (n.as_i64(), n.as_f64()) {
        (Some(i), _) => i.to_string(),
        (None, Some(f)) if f.abs() >= 1e4 || f == 0.0 => format!("{f:.1}"),
        (None, Some(f)) => format!("{f:.4}"),
        _ => n.to_string(),
    }
}

/// Positions of a TUM trajectory as float32.
pub fn positions(path: &Path) -> Result<Vec<[f32; 3]>> {
    let t = keylo::io::trajectory::read_tum(path)
        .with_context(|| format!("reading {}", path.display()))?;
    let points = keylo::eval::align::positions(&t);
    Ok(points
        .iter()
        .map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect())
}

/// The reference's name in a run's summary (the file name of its `ground_truth`).
pub fn reference_label(summary: &Value) -> Option<String> {
    let path = summary.get("ground_truth")?.as_str()?;
    Some(crate::reference_args::file_label(Path::new(path)))
}

/// The final local map, the estimated trajectory and (when the run had one) the aligned
/// reference, in the world frame of the run; `None` when the run has none of them (an
/// unreadable file is noted).
pub fn map_scene(
    dir: &Path,
    reference_label: &str,
    limits: Limits,
    notes: &mut Notes,
) -> Option<Scene> {
    let mut scene = Scene {
        title: format!("local map and trajectory of {}", dir.display()),
        clouds: Vec::new(),
        lines: Vec::new(),
    };
    let map = dir.join("map.ply");
    if map.is_file() {
        if let Some(points) = soft(crate::cloud_ply::read(&map), notes) {
            let name = "local map after the last frame";
            scene
                .clouds
                .push(Cloud::thinned(name, MAP, 1.5, &points, limits.max_points));
        }
    }
    let reference = dir.join(crate::reference_out::FILE);
    let name = format!("{reference_label} (aligned as for the accuracy figures)");
    push_path(&mut scene, &reference, &name, (REFERENCE, 7.0), notes);
    let est = dir.join("trajectory.tum");
    push_path(
        &mut scene,
        &est,
        "keylo's trajectory",
        (ESTIMATE, 3.0),
        notes,
    );
    (!scene.clouds.is_empty() || !scene.lines.is_empty()).then_some(scene)
}

/// Adds the trajectory at `path` (when the file exists) as a line of `(colour, dot size)`.
pub fn push_path(
    scene: &mut Scene,
    path: &Path,
    name: &str,
    (colour, size): (&str, f32),
    notes: &mut Notes,
) {
    if path.is_file() {
        if let Some(p) = soft(positions(path), notes) {
            scene.lines.push(Polyline::new(name, colour, size, &p));
        }
    }
}
