//! `keylo sim realism`: how far the simulator's images are from real ones — per detector the
//! keypoint count and the other metrics of the keypoint study, and the distances between the
//! intensity and gradient-magnitude histograms, for every simulated channel against a folder
//! of real images.

mod report;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use clap::Args;
use keylo::features::image::{Normalise, NormaliseMethod};
use keylo::kpeval::realism::{shifts, Histograms};
use keylo::kpeval::{evaluate, summarise, ComboSummary, EvalOptions, EvalSpec, Plane, Quartiles};
use keylo::sim::{SimConfig, Simulator};
use keylo::{BuildContext, Channel};

use crate::keypoints::eval::progress;

/// The seven detectors of the realism goal, each with a descriptor OpenCV ships (so match
/// ratio and match score are OpenCV's own).
pub const DEFAULT_COMBOS: &str =
    "AKAZE_AKAZE,ORB_ORB,FAST_BRISK,SHITOMASI_BRISK,HARRIS_BRISK,SIFT_SIFT,BRISK_BRISK";

#[derive(Debug, Args)]
pub struct RealismArgs {
    /// A folder of real LiDAR images (PNG, natural name order), e.g.
    /// ../shared/data/tiers_signal (OS0-128 signal images of Ouster's ROS driver).
    #[arg(long)]
    pub real: PathBuf,
    /// Real images used (the first N).
    #[arg(long, default_value_t = 100)]
    pub real_frames: usize,
    /// Scene simulated: lab, corridor, road, park (see `keylo sim --help`).
    #[arg(long, default_value = "lab")]
    pub scene: String,
    /// Simulated frames per seed.
    #[arg(long, default_value_t = 25)]
    pub frames: usize,
    /// Scene layouts simulated: seeds `seed`, `seed + 1`, … (each its own sequence; the
    /// statistics pool them, so they do not rest on one random layout).
    #[arg(long, default_value_t = 4)]
    pub seeds: usize,
    /// Any other simulator parameter, e.g. --set seed=3.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Simulated channels compared with the real images.
    #[arg(long, default_value = "signal,reflectivity,near-ir,range")]
    pub channels: String,
    /// Counts → grey level of the simulated signal as `counts · S` instead of the way the
    /// real images were made. By default the signal becomes 8-bit as Ouster's ROS driver
    /// makes its signal images, which the TIERS images are: auto exposure on the 10th and
    /// 90th percentiles, then a square root (`[image.normalise] method = "ouster-ros"`). The
    /// signal is also evaluated with keylo's default per-frame stretch (`signal-stretched`);
    /// other channels always are.
    #[arg(long, value_name = "S")]
    pub signal_scale: Option<f64>,
    /// Detector/descriptor combinations evaluated.
    #[arg(long, default_value = DEFAULT_COMBOS)]
    pub combos: String,
    /// Combinations evaluated at a time (default: one per core).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Output folder: realism.md, realism.csv, histograms.csv, realism.json.
    #[arg(long)]
    pub out: PathBuf,
}

/// One set of images compared: the real ones or one simulated channel.
pub struct ImageSet {
    pub name: String,
    pub histograms: Histograms,
    /// Median horizontal shift between consecutive images, pixels.
    pub shift: Option<f64>,
    /// Sequences the images come from (simulated: one per seed).
    pub sequences: usize,
    pub summaries: Vec<ComboSummary>,
}

pub fn run(args: RealismArgs, threads: Option<usize>, quiet: bool) -> Result<ExitCode> {
    let spec = EvalSpec::default();
    let real = real_planes(&args, &spec.image.normalise)?;
    let channels = channels(&args.channels)?;
    if args.frames < 2 {
        bail!(
            "--frames {}: the match metrics need at least 2",
            args.frames
        );
    }
    if args.seeds == 0 {
        bail!("--seeds 0: expected at least 1");
    }
    let jobs = crate::keypoints::input::jobs(args.jobs, threads)?;
    let mut inputs: Vec<(String, Vec<Vec<Plane>>)> = vec![("real".into(), vec![real])];
    let config = crate::cmd_sim::setup::sim_config(&args.scene, args.frames, &args.sets)?;
    for k in 0..args.seeds {
        let seeded = SimConfig {
            seed: config.seed + k as u64,
            ..config.clone()
        };
        let sim = Simulator::new(&seeded)?;
        let sets = sim_planes(&sim, &channels, args.signal_scale);
        if inputs.len() == 1 {
            inputs.extend(sets.into_iter().map(|(name, p)| (name, vec![p])));
        } else {
            for ((_, runs), (_, p)) in inputs.iter_mut().skip(1).zip(sets) {
                runs.push(p);
            }
        }
    }
    let registry = keylo::registry();
    let set = keylo::kpeval::ComboSet::parse(&args.combos);
    let combos = keylo::kpeval::parse_combos(&set, &registry).context("--combos")?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let ctx = BuildContext::default();
    let mut sets = Vec::new();
    for (name, runs) in inputs {
        let bar = progress(quiet, &format!("{name:>18}"));
        let tick = |done: usize, total: usize| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        };
        let opts = EvalOptions {
            jobs,
            skip_unavailable: false,
            progress: Some(&tick),
        };
        let (mut rows, mut moved) = (Vec::new(), Vec::new());
        for planes in &runs {
            let result = evaluate(planes, &combos, &spec, &registry, &ctx, &opts)
                .with_context(|| format!("evaluating the {name} images"))?;
            if let Some((combo, why)) = result.failed.first() {
                bail!("{name} images: {combo} failed: {why}");
            }
            rows.extend(result.rows);
            moved.extend(shifts(planes, &spec.image)?);
        }
        bar.finish_and_clear();
        sets.push(ImageSet {
            histograms: Histograms::of(runs.iter().flatten(), &spec.image)?,
            shift: Quartiles::of(&moved).map(|q| q.median),
            sequences: runs.len(),
            summaries: summarise(&rows),
            name,
        });
    }
    let heading = format!(
        "`keylo sim realism --real {} --real-frames {} --scene {} --frames {} --seeds {}{}`",
        args.real.display(),
        args.real_frames,
        args.scene,
        args.frames,
        args.seeds,
        args.sets
            .iter()
            .map(|s| format!(" --set {s}"))
            .collect::<String>()
    );
    let md = report::write(&args.out, &sets, &heading)?;
    if !quiet {
        print!("{md}");
        println!("\nresults in {}", args.out.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The first `--real-frames` PNG files of `--real`.
fn real_planes(args: &RealismArgs, normalise: &Normalise) -> Result<Vec<Plane>> {
    let files = crate::keypoints::input::png_files(&args.real);
    if files.len() < 2 {
        bail!(
            "--real {}: expected a folder with at least 2 PNG images, found {}",
            args.real.display(),
            files.len()
        );
    }
    files
        .iter()
        .take(args.real_frames.max(2))
        .map(|p| Plane::from_png(p, normalise).map_err(Into::into))
        .collect()
}

fn channels(list: &str) -> Result<Vec<Channel>> {
    let channels: Vec<Channel> = list
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse()
                .map_err(|e: String| anyhow::anyhow!("--channels: {e}"))
        })
        .collect::<Result<_>>()?;
    if channels.is_empty() {
        bail!("--channels {list:?}: expected at least one of range, signal, reflectivity, near-ir");
    }
    Ok(channels)
}

/// Every simulated frame's image of each channel: the signal as the real images were made
/// (or `counts · scale`) and stretched as keylo does by default; other channels stretched.
fn sim_planes(
    sim: &Simulator,
    channels: &[Channel],
    scale: Option<f64>,
) -> Vec<(String, Vec<Plane>)> {
    let stretched = Normalise::default();
    let fixed = match scale {
        Some(scale) => Normalise {
            method: NormaliseMethod::Fixed,
            scale,
            ..Normalise::default()
        },
        None => Normalise {
            method: NormaliseMethod::OusterRos,
            ..Normalise::default()
        },
    };
    let mut sets: Vec<(String, Normalise, Channel)> = Vec::new();
    for &c in channels {
        if c == Channel::Signal {
            sets.push(("signal".into(), fixed.clone(), c));
            sets.push(("signal-stretched".into(), stretched.clone(), c));
        } else {
            sets.push((c.name().into(), stretched.clone(), c));
        }
    }
    let mut planes: Vec<Vec<Plane>> = vec![Vec::new(); sets.len()];
    for i in 0..sim.len() {
        let frame = sim.frame(i);
        for ((_, normalise, channel), out) in sets.iter().zip(&mut planes) {
            out.push(Plane::from_frame(
                &frame,
                *channel,
                normalise,
                format!("frame {i}"),
            ));
        }
    }
    sets.into_iter()
        .zip(planes)
        .map(|((name, _, _), p)| (format!("sim {name}"), p))
        .collect()
}
