//! What a report shows of one run folder (`keylo run --out DIR`): its summary, the local
//! map with the trajectory and the reference, one frame's raw and registered points, the
//! pictures of `--images`, per-frame plots.

use std::path::Path;

use anyhow::{Context, Result};
use serde_json::Value;

use super::html::{self, escape};
use super::scene::{Cloud, Polyline, Scene};
use crate::overlay::Pictured;

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
    Ok(t.poses
        .iter()
        .map(|p| {
            let v = p.translation.vector;
            [v.x as f32, v.y as f32, v.z as f32]
        })
        .collect())
}

/// The final local map, the estimated trajectory and (when the run had one) the aligned
/// reference, in the world frame of the run; `None` with a note when the run has neither a
/// map nor a trajectory.
pub fn map_scene(dir: &Path, reference_label: &str, limits: Limits) -> Result<Option<Scene>> {
    let mut scene = Scene {
        title: format!("local map and trajectory of {}", dir.display()),
        clouds: Vec::new(),
        lines: Vec::new(),
    };
    let map = dir.join("map.ply");
    if map.is_file() {
        let points = crate::cloud_ply::read(&map)?;
        let cloud = Cloud::thinned(
            "local map after the last frame",
            MAP,
            1.5,
            &points,
            limits.max_points,
        );
        scene.clouds.push(cloud);
    }
    let reference = dir.join(crate::reference_out::FILE);
    if reference.is_file() {
        let name = format!("{reference_label} (aligned as for the accuracy figures)");
        scene.lines.push(Polyline::new(
            &name,
            REFERENCE,
            7.0,
            &positions(&reference)?,
        ));
    }
    let est = dir.join("trajectory.tum");
    if est.is_file() {
        scene.lines.push(Polyline::new(
            "keylo's trajectory",
            ESTIMATE,
            3.0,
            &positions(&est)?,
        ));
    }
    Ok((!scene.clouds.is_empty() || !scene.lines.is_empty()).then_some(scene))
}

/// The `images/pictures.json` list of `keylo run --images`, if the run has one.
pub fn pictured(dir: &Path) -> Result<Option<Vec<Pictured>>> {
    let path = dir.join("images").join(crate::overlay::INDEX);
    if !path.is_file() {
        return Ok(None);
    }
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let list = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a list of pictured frames", path.display()))?;
    Ok(Some(list))
}

/// One frame's raw points and the registered ones (sensor frame).
pub fn frame_scene(dir: &Path, pictured: &[Pictured], limits: Limits) -> Result<Option<Scene>> {
    let Some((frame, [raw, selected])) = pictured
        .iter()
        .find_map(|p| p.clouds.clone().map(|c| (p.frame, c)))
    else {
        return Ok(None);
    };
    let images = dir.join("images");
    let raw = crate::cloud_ply::read(&images.join(raw))?;
    let selected = crate::cloud_ply::read(&images.join(selected))?;
    Ok(Some(Scene {
        title: format!("frame {frame}: raw and registered points"),
        clouds: vec![
            Cloud::thinned("raw points", MAP, 1.5, &raw, limits.max_points),
            Cloud::thinned(
                "points given to the registrar",
                SELECTED,
                3.5,
                &selected,
                limits.max_points,
            ),
        ],
        lines: Vec::new(),
    }))
}

/// The pictures of at most `max` frames, spread evenly over those pictured.
pub fn pictures_html(dir: &Path, pictured: &[Pictured], max: usize) -> Result<String> {
    let step = pictured.len().div_ceil(max.max(1)).max(1);
    let mut out = String::new();
    if step > 1 {
        out.push_str(&format!(
            "<p class=\"note\">{} frames were pictured; one in {step} is shown here (all are in {}).</p>",
            pictured.len(),
            escape(&dir.join("images").display().to_string())
        ));
    }
    let images = dir.join("images");
    for p in pictured.iter().step_by(step) {
        out.push_str(&format!(
            "<h3>Frame {}</h3><div class=\"pictures\">",
            p.frame
        ));
        for i in &p.images {
            let caption = format!(
                "{}: {} keypoints (yellow circles: size and orientation, red: position); \
                 tinted blue: pixels whose points were registered",
                i.image, i.keypoints
            );
            out.push_str(&png_figure(&images.join(&i.file), &caption)?);
        }
        out.push_str("</div><div class=\"pictures top\">");
        let t = &p.top;
        let caption = format!(
            "from above, forward up: {} raw points (grey), {} registered (orange); rings every {} m, edge at {} m",
            t.raw_points, t.selected_points, t.ring_step_m, t.half_extent_m
        );
        out.push_str(&png_figure(&images.join(&t.file), &caption)?);
        out.push_str("</div>");
    }
    Ok(out)
}

fn png_figure(path: &Path, caption: &str) -> Result<String> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let name = path
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    Ok(html::figure(
        &html::image("image/png", &bytes, &name),
        caption,
    ))
}
