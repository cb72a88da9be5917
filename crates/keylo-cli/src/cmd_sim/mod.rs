//! `keylo sim`: simulate a sequence and write it as a keylo frame folder or KITTI .bin files.

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use indicatif::ProgressBar;
use keylo::io::frames::FramesWriter;
use keylo::io::kitti_bin::write_kitti_bin;
use keylo::sim::Simulator;
use keylo::Trajectory;

mod args;
pub mod setup;

pub use args::{SimArgs, SimCommand, SimFormat};
use setup::sim_config;

pub fn run(args: SimArgs, threads: Option<usize>, quiet: bool) -> Result<ExitCode> {
    if let Some(SimCommand::Realism(r)) = args.command {
        return crate::realism::run(r, threads, quiet);
    }
    let Some(out) = args.out.clone() else {
        anyhow::bail!("keylo sim: --out DIR is required");
    };
    let config = sim_config(&args.scene, args.frames, &args.sets)?;
    let sim = Simulator::new(&config)?;
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let progress = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(sim.len() as u64)
    };
    let gt = sim.ground_truth();
    let description = format!("keylo sim {}", args_line(&args));
    match args.format {
        SimFormat::Frames => write_frames(&sim, &out, &description, &progress)?,
        SimFormat::KittiBin => write_bins(&sim, &out, &progress)?,
    }
    progress.finish_and_clear();
    let gt = match args.format {
        SimFormat::Frames => gt,
        // Other tools stamp frames by index: do the same so the trajectories associate.
        SimFormat::KittiBin => Trajectory {
            stamps: (0..gt.len()).map(|i| i as f64).collect(),
            poses: gt.poses,
        },
    };
    let gt_path = out.join("gt.tum");
    keylo::io::trajectory::write_tum(&gt_path, &gt)
        .with_context(|| format!("writing {}", gt_path.display()))?;
    if !quiet {
        println!("wrote {} frames and gt.tum to {}", sim.len(), out.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn args_line(args: &SimArgs) -> String {
    let sets: Vec<String> = args.sets.iter().map(|s| format!("--set {s}")).collect();
    format!(
        "--scene {} --frames {} {}",
        args.scene,
        args.frames,
        sets.join(" ")
    )
}

fn write_frames(
    sim: &Simulator,
    out: &Path,
    description: &str,
    progress: &ProgressBar,
) -> Result<()> {
    let first = sim.frame(0);
    let mut writer = FramesWriter::create(
        out,
        first.rows,
        first.cols,
        (*first.beams).clone(),
        description,
    )?;
    writer.write(&first)?;
    progress.inc(1);
    for i in 1..sim.len() {
        writer.write(&sim.frame(i))?;
        progress.inc(1);
    }
    writer.finish()?;
    Ok(())
}

fn write_bins(sim: &Simulator, out: &Path, progress: &ProgressBar) -> Result<()> {
    let dir = out.join("velodyne");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    keylo::io::remove_files_with_extension(&dir, "bin")?;
    for i in 0..sim.len() {
        write_kitti_bin(&dir.join(format!("{i:06}.bin")), &sim.frame(i))?;
        progress.inc(1);
    }
    Ok(())
}
