//! How honest keylo's pose covariance is, and the noise model that makes it so: the
//! normalised estimation error squared (NEES) of the pose graph's keyframe edges (and of
//! single frames) against the simulator's ground truth, per registrar, over several seeds of
//! two scenes (docs/maps.md, docs/results/maps.md).
//!
//! For each motion `Δ = T_a⁻¹ · T_b` (between keyframes, a map's default of 1 m or 10°; or
//! between consecutive frames), `ε = log(Δ̂⁻¹ · Δ_true)` and `NEES = εᵀ Σ⁻¹ ε`, with `Σ` what
//! `keylo::map::PoseGraph` writes into `pose_graph.g2o`. Two covariances:
//! - `σ² H⁻¹` alone (σ = 0.03 m), keylo's per-frame estimate summed along the edge;
//! - keylo's model (`keylo::map::covariance::NoiseModel`): `s · H⁻¹` plus noise growing with
//!   the distance `d` each frame moved and the angle `a` it turned,
//!   `diag((κ_t d)² I₃, ((κ_r d)² + (κ_a a)²) I₃)` (odometry drift grows with the motion).
//!   `s, κ_t, κ_r, κ_a` are fitted on the keyframe edges
//!   of the first half of the seeds of both scenes (mean NEES 6, and 3 for each of the
//!   translation and rotation blocks), by a grid search, and checked on the second half.
//!
//! A calibrated covariance gives a mean NEES of 6 (six degrees of freedom).
//!
//! Usage: covariance_nees [SEEDS] [FRAMES] [REGISTRAR...]   (defaults: 8 60, all three)

use keylo::config::RawConfig;
use keylo::map::covariance::NoiseModel;
use keylo::map::PoseGraph;
use keylo::registration::se3;
use keylo::sim::{SceneKind, SimConfig, Simulator};
use keylo::Pose;
use nalgebra::{Matrix6, Vector6};

/// The pipelines: raw clouds, each registrar with its defaults (hybrid with the keypoints of
/// configs/examples/raw-hybrid.toml).
const PIPELINES: [(&str, &str); 3] = [
    ("kiss-icp", "[registrar]\nkind = \"kiss-icp\"\n"),
    ("ndt", "[registrar]\nkind = \"ndt\"\n"),
    (
        "hybrid",
        "[image]\nkind = \"lidar\"\nimages = [\"signal\", \"range\"]\nwidth = 1024\nheight = 64\n\
         [detector]\nkind = \"fast\"\nthreshold = 10\n[descriptor]\nkind = \"freak\"\n\
         [registrar]\nkind = \"hybrid\"\n",
    ),
];

const SCENES: [SceneKind; 2] = [SceneKind::Lab, SceneKind::Road];

/// One motion (a keyframe edge, or one frame): its error against the ground truth and its
/// covariance `s·A + κ_t²·B + κ_r²·C` split by the model's parameters.
struct Sample {
    e: Vector6<f64>,
    parts: [Matrix6<f64>; 4],
}

impl Sample {
    fn covariance(&self, m: &NoiseModel) -> Matrix6<f64> {
        self.parts[0] * m.scale
            + self.parts[1] * m.kappa_t.powi(2)
            + self.parts[2] * m.kappa_r.powi(2)
            + self.parts[3] * m.kappa_a.powi(2)
    }
}

/// A pose graph edge: from, to, measured motion, covariance.
type Edge = (usize, usize, Pose, Matrix6<f64>);

/// The basis models: `H⁻¹`, translation per metre, rotation per metre, rotation per radian.
const BASIS: [NoiseModel; 4] = [
    basis([1.0, 0.0, 0.0, 0.0]),
    basis([0.0, 1.0, 0.0, 0.0]),
    basis([0.0, 0.0, 1.0, 0.0]),
    basis([0.0, 0.0, 0.0, 1.0]),
];

const fn basis(v: [f64; 4]) -> NoiseModel {
    NoiseModel {
        scale: v[0],
        kappa_t: v[1],
        kappa_r: v[2],
        kappa_a: v[3],
    }
}

/// The motions of one simulated run: `(keyframe edges, frames)`, keyframes as a map's
/// default (1 m or 10°).
fn run(
    pipeline: &str,
    sim: &Simulator,
) -> Result<(Vec<Sample>, Vec<Sample>), Box<dyn std::error::Error>> {
    let registry = keylo::registry();
    let config = registry.resolve(&RawConfig::parse("nees", pipeline)?)?;
    let mut odometry = keylo::Odometry::build(&config, &registry)?;
    let mut results = Vec::new();
    let mut truth: Vec<Pose> = Vec::new();
    for k in 0..sim.len() {
        results.push(odometry.process(&sim.frame(k))?);
        truth.push(sim.relative_pose_at(sim.gt_stamp(k)));
    }
    // The first frames build the map: motions start at frame 1.
    let samples = |distance: f64, angle: f64| -> Result<Vec<Sample>, Box<dyn std::error::Error>> {
        let mut graphs = BASIS.map(|m| PoseGraph::new(distance, angle, m));
        let mut taken = Vec::new();
        for (k, r) in results.iter().enumerate().skip(1) {
            let took: Vec<bool> = graphs.iter_mut().map(|g| g.add(r)).collect();
            if took[0] {
                taken.push(k);
            }
        }
        if graphs[0].fallbacks > 0 {
            return Err(format!(
                "{} frames without a covariance estimate",
                graphs[0].fallbacks
            )
            .into());
        }
        let edges: Vec<Vec<Edge>> = graphs
            .iter()
            .map(|g| g.edges().map(|(a, b, m, c)| (a, b, *m, *c)).collect())
            .collect();
        Ok((0..edges[0].len())
            .map(|i| {
                let (a, b, measured, _) = edges[0][i];
                let (ka, kb) = (taken[a], taken[b]);
                Sample {
                    e: se3::log(&(measured.inverse() * (truth[ka].inverse() * truth[kb]))),
                    parts: [edges[0][i].3, edges[1][i].3, edges[2][i].3, edges[3][i].3],
                }
            })
            .collect())
    };
    Ok((samples(1.0, 10.0)?, samples(0.0, 0.0)?))
}

/// NEES of `s` under `cov`, whole and per block (translation, rotation).
fn nees(s: &Sample, cov: &Matrix6<f64>) -> Option<[f64; 3]> {
    let inv = cov.try_inverse()?;
    let whole = (s.e.transpose() * inv * s.e)[(0, 0)];
    let block = |o: usize| {
        let c = cov.fixed_view::<3, 3>(o, o).into_owned();
        let e = s.e.fixed_rows::<3>(o).into_owned();
        c.try_inverse().map(|i| (e.transpose() * i * e)[(0, 0)])
    };
    Some([whole, block(0)?, block(3)?])
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(s.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Mean NEES (whole, translation, rotation) of `samples` under `model`.
fn means(samples: &[&Sample], model: &NoiseModel) -> [f64; 3] {
    let v: Vec<[f64; 3]> = samples
        .iter()
        .filter_map(|s| nees(s, &s.covariance(model)))
        .collect();
    std::array::from_fn(|k| mean(&v.iter().map(|x| x[k]).collect::<Vec<_>>()))
}

/// The model whose mean NEES is closest to (6, 3, 3) in every scene (log ratios, squared).
fn fit(per_scene: &[Vec<&Sample>]) -> NoiseModel {
    let logspace = |lo: f64, hi: f64, n: usize| -> Vec<f64> {
        (0..n)
            .map(|i| 10f64.powf(lo + (hi - lo) * i as f64 / (n - 1) as f64))
            .collect()
    };
    let mut kappas_t = vec![0.0];
    kappas_t.extend(logspace(-4.0, 0.0, 17));
    let mut kappas_r = vec![0.0];
    kappas_r.extend(logspace(-5.0, -1.0, 17));
    let mut kappas_a = vec![0.0];
    kappas_a.extend(logspace(-3.0, 0.0, 13));
    let rotations: Vec<(f64, f64)> = (kappas_r.iter())
        .flat_map(|&r| kappas_a.iter().map(move |&a| (r, a)))
        .collect();
    let mut best = (f64::INFINITY, NoiseModel::default());
    for &scale in &logspace(-5.0, 1.0, 25) {
        for &kappa_t in &kappas_t {
            for &(kappa_r, kappa_a) in &rotations {
                let model = NoiseModel {
                    scale,
                    kappa_t,
                    kappa_r,
                    kappa_a,
                };
                let cost: f64 = per_scene
                    .iter()
                    .map(|s| {
                        let m = means(s, &model);
                        (m[0] / 6.0).ln().powi(2)
                            + (m[1] / 3.0).ln().powi(2)
                            + (m[2] / 3.0).ln().powi(2)
                    })
                    .sum();
                if cost < best.0 {
                    best = (cost, model);
                }
            }
        }
    }
    best.1
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let seeds: u64 = args.next().map_or(Ok(8), |s| s.parse())?;
    let frames: usize = args.next().map_or(Ok(60), |s| s.parse())?;
    let only: Vec<String> = args.collect();
    if seeds < 2 || frames < 4 {
        return Err("expected at least 2 seeds and 4 frames".into());
    }
    let half = seeds / 2;
    println!(
        "{seeds} seeds × {frames} frames per scene; fitted on seeds 0–{}, checked on {half}–{}",
        half - 1,
        seeds - 1
    );
    println!("| registrar | scene | edges checked | σ²H⁻¹ alone (σ = 0.03 m): mean NEES | model: mean NEES (translation, rotation) | median | per-seed mean (min–max) | frames: mean NEES |");
    println!("|---|---|---|---|---|---|---|---|");
    for (name, pipeline) in PIPELINES
        .iter()
        .filter(|(n, _)| only.is_empty() || only.iter().any(|o| o == n))
    {
        // runs[scene][seed] = (keyframe edges, frames)
        let mut runs = Vec::new();
        for scene in SCENES {
            let mut per_seed = Vec::new();
            for seed in 0..seeds {
                let sim = Simulator::new(&SimConfig {
                    scene,
                    frames,
                    seed,
                    ..SimConfig::default()
                })?;
                per_seed.push(run(pipeline, &sim)?);
            }
            runs.push(per_seed);
        }
        let h = half as usize;
        let fit_set: Vec<Vec<&Sample>> = runs
            .iter()
            .map(|s| s[..h].iter().flat_map(|r| &r.0).collect())
            .collect();
        let model = fit(&fit_set);
        let plain = NoiseModel::plain(0.03);
        for (scene, per_seed) in SCENES.iter().zip(&runs) {
            let edges: Vec<&Sample> = per_seed[h..].iter().flat_map(|r| &r.0).collect();
            let frames: Vec<&Sample> = per_seed[h..].iter().flat_map(|r| &r.1).collect();
            let m = means(&edges, &model);
            let all: Vec<f64> = edges
                .iter()
                .filter_map(|s| nees(s, &s.covariance(&model)).map(|v| v[0]))
                .collect();
            let seed_means: Vec<f64> = per_seed[h..]
                .iter()
                .map(|r| means(&r.0.iter().collect::<Vec<_>>(), &model)[0])
                .collect();
            println!(
                "| {name} | {scene:?} | {} | {:.0} | {:.2} ({:.2}, {:.2}) | {:.2} | {:.2}–{:.2} | {:.2} |",
                edges.len(),
                means(&edges, &plain)[0],
                m[0],
                m[1],
                m[2],
                median(&all),
                seed_means.iter().copied().fold(f64::INFINITY, f64::min),
                seed_means.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                means(&frames, &model)[0],
            );
        }
        println!(
            "  {name}: NoiseModel {{ scale: {:e}, kappa_t: {:e}, kappa_r: {:e}, kappa_a: {:e} }}",
            model.scale, model.kappa_t, model.kappa_r, model.kappa_a
        );
    }
    Ok(())
}
