//! `keylo sim realism`: how far the simulator's images are from real ones — per detector the
//! keypoint count and the other metrics of the keypoint study, and the distances between the
//! intensity and gradient-magnitude histograms, for every simulated channel against a folder
//! of real images.

mod motion;
mod report;
mod side_by_side;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use clap::Args;
use keylo::features::image::{Normalise, NormaliseMethod};
use keylo::kpeval::motion::steps;
use keylo::kpeval::realism::Histograms;
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
    /// Real images used (N from `--real-start`).
    #[arg(long, default_value_t = 100)]
    pub real_frames: usize,
    /// First real image used (in name order). The `ouster` lab's clutter was tuned on the
    /// median counts of the whole TIERS recording (its 1146 images:
    /// scripts/study/tiers_images.sh), from views along the lab's whole walk; the sensor is
    /// nearly still over 0–49 and the last ~150 images (1046–1145), and moves in between.
    #[arg(long, default_value_t = 0)]
    pub real_start: usize,
    /// Also compare a moving simulated sensor with a moving real stretch: `--real-frames`
    /// images from FIRST (e.g. 200: the TIERS sensor moves through the room from about image
    /// 50 on), the simulated motion matched to the real one's (its speed and sway scaled until
    /// the median horizontal shift and the median change beyond it between consecutive images
    /// are the real stretch's), and report
    /// still and moving side by side (realism.md; each in full in still/ and moving/). The
    /// still half then holds the simulated sensor still.
    #[arg(long, value_name = "FIRST")]
    pub moving_start: Option<usize>,
    /// Where on its loop the moving simulated sensor starts, as a share of the lap
    /// (`start_lap`): the lab's walk runs straightest a quarter lap on, where it turns least
    /// for the way it travels, as the real sensor does.
    #[arg(long, value_name = "SHARE", default_value_t = 0.25)]
    pub moving_lap: f64,
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
    /// How consecutive images differ: median horizontal shift, pixels, and median change
    /// beyond it, grey levels (`keylo::kpeval::motion::Step`); `None` without two images.
    pub moved: Option<Moved>,
    /// Sequences the images come from (simulated: one per seed).
    pub sequences: usize,
    pub summaries: Vec<ComboSummary>,
}

pub fn run(args: RealismArgs, threads: Option<usize>, quiet: bool) -> Result<ExitCode> {
    if args.frames < 2 {
        bail!(
            "--frames {}: the match metrics need at least 2",
            args.frames
        );
    }
    if args.seeds == 0 {
        bail!("--seeds 0: expected at least 1");
    }
    let lap = SimConfig {
        start_lap: args.moving_lap,
        ..SimConfig::default()
    };
    if let Err(e) = lap.validate() {
        bail!("--moving-lap {}: {e}", args.moving_lap);
    }
    let channels = channels(&args.channels)?;
    let config = crate::cmd_sim::setup::sim_config(&args.scene, args.frames, &args.sets)?;
    let ctx = Protocol {
        args: &args,
        channels: &channels,
        jobs: crate::keypoints::input::jobs(args.jobs, threads)?,
        quiet,
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let Some(moving_start) = args.moving_start else {
        let sets = ctx.protocol(real_planes(&args, args.real_start)?, &config, "")?;
        let md = report::write(&args.out, &sets, &heading(&args, ""))?;
        if !quiet {
            print!("{md}");
            println!("\nresults in {}", args.out.display());
        }
        return Ok(ExitCode::SUCCESS);
    };
    let still_config = SimConfig {
        speed_scale: 0.0,
        sway_scale: 0.0,
        ..config.clone()
    };
    // Both real stretches are read first: a bad `--moving-start` fails before any work.
    let (real_still, real_moving) = (
        real_planes(&args, args.real_start)?,
        real_planes(&args, moving_start)?,
    );
    let still = ctx.protocol(real_still, &still_config, "still")?;
    let motion = motion::matched(
        &config,
        median_motion(&real_moving)?,
        args.moving_lap,
        args.seeds,
        quiet,
    )?;
    let moving = ctx.protocol(real_moving, &motion.config, "moving")?;
    for (name, sets) in [("still", &still), ("moving", &moving)] {
        let dir = args.out.join(name);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        report::write(&dir, sets, &heading(&args, name))?;
    }
    let md = side_by_side::write(
        &args.out,
        side_by_side::Halves {
            still: &still,
            moving: &moving,
            still_first: args.real_start,
            moving_first: moving_start,
            motion: &motion,
        },
        &heading(&args, "both"),
    )?;
    if !quiet {
        print!("{md}");
        println!("\nresults in {}", args.out.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The command line, for the reports' headings; `half` names the half reported.
fn heading(args: &RealismArgs, half: &str) -> String {
    let moving = args
        .moving_start
        .map_or(String::new(), |m| format!(" --moving-start {m}"));
    let line = format!(
        "`keylo sim realism --real {} --real-start {} --real-frames {}{moving} --scene {} \
         --frames {} --seeds {}{}`",
        args.real.display(),
        args.real_start,
        args.real_frames,
        args.scene,
        args.frames,
        args.seeds,
        args.sets
            .iter()
            .map(|s| format!(" --set {s}"))
            .collect::<String>()
    );
    match half {
        "" | "both" => line,
        h => format!("{line} — the {h} half"),
    }
}

/// How consecutive images of `planes` differ (at the study's size): the median horizontal
/// shift, pixels, and the median change beyond it, grey levels.
pub(crate) fn median_motion(planes: &[Plane]) -> Result<Moved> {
    let steps = steps(planes, &EvalSpec::default().image)?;
    Ok(Moved::of(&steps))
}

/// Median shift and change of a set of steps (0 without any).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Moved {
    pub shift: f64,
    pub change: f64,
}

impl Moved {
    pub(crate) fn of(steps: &[keylo::kpeval::motion::Step]) -> Self {
        let median = |f: fn(&keylo::kpeval::motion::Step) -> f64| {
            let v: Vec<f64> = steps.iter().map(f).collect();
            Quartiles::of(&v).map_or(0.0, |q| q.median)
        };
        Self {
            shift: median(|s| s.shift),
            change: median(|s| s.change),
        }
    }
}

/// What every protocol shares.
struct Protocol<'a> {
    args: &'a RealismArgs,
    channels: &'a [Channel],
    jobs: usize,
    quiet: bool,
}

impl Protocol<'_> {
    /// The `real` images and every simulated channel of `config`'s layouts (seeds `seed` …
    /// `seed + seeds − 1`), evaluated: the real set first. `label` prefixes the progress
    /// lines.
    fn protocol(&self, real: Vec<Plane>, config: &SimConfig, label: &str) -> Result<Vec<ImageSet>> {
        let spec = EvalSpec::default();
        let mut inputs: Vec<(String, Vec<Vec<Plane>>)> = vec![("real".into(), vec![real])];
        for k in 0..self.args.seeds {
            let seeded = SimConfig {
                seed: config.seed + k as u64,
                ..config.clone()
            };
            let sim = Simulator::new(&seeded)?;
            let sets = sim_planes(&sim, self.channels, self.args.signal_scale);
            if inputs.len() == 1 {
                inputs.extend(sets.into_iter().map(|(name, p)| (name, vec![p])));
            } else {
                for ((_, runs), (_, p)) in inputs.iter_mut().skip(1).zip(sets) {
                    runs.push(p);
                }
            }
        }
        let registry = keylo::registry();
        let set = keylo::kpeval::ComboSet::parse(&self.args.combos);
        let combos = keylo::kpeval::parse_combos(&set, &registry).context("--combos")?;
        let ctx = BuildContext::default();
        let mut sets = Vec::new();
        for (name, runs) in inputs {
            let bar = progress(self.quiet, &format!("{label:>6} {name:>18}"));
            let tick = |done: usize, total: usize| {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            };
            let opts = EvalOptions {
                jobs: self.jobs,
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
                moved.extend(steps(planes, &spec.image)?);
            }
            bar.finish_and_clear();
            sets.push(ImageSet {
                histograms: Histograms::of(runs.iter().flatten(), &spec.image)?,
                moved: (!moved.is_empty()).then(|| Moved::of(&moved)),
                sequences: runs.len(),
                summaries: summarise(&rows),
                name,
            });
        }
        Ok(sets)
    }
}

/// `--real-frames` PNG files of `--real` from the `first` (in name order), as the keypoint
/// study takes PNG images.
fn real_planes(args: &RealismArgs, first: usize) -> Result<Vec<Plane>> {
    let normalise = EvalSpec::default().image.png_normalise();
    let files = crate::keypoints::input::png_files(&args.real);
    let wanted = args.real_frames.max(2);
    if files.len() < first.saturating_add(2) {
        bail!(
            "--real {}: expected at least 2 PNG images from image {first} on, the folder has \
             {} in all",
            args.real.display(),
            files.len()
        );
    }
    files
        .iter()
        .skip(first)
        .take(wanted)
        .map(|p| Plane::from_png(p, &normalise).map_err(Into::into))
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
pub(crate) fn sim_planes(
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
