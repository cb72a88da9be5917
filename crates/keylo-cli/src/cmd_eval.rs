//! `keylo eval`: ATE/RPE of one trajectory against another.

use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use keylo::eval::associate::{associate_labeled, AssociateOptions};
use keylo::eval::coverage::{of_evaluation, range_text, Coverage, EvalDocument};
use keylo::eval::rpe::{rpe, Delta, RpeOptions};
use keylo::eval::{evaluate, EvalOptions};

use std::path::PathBuf;

use crate::{reference_args, trajectories};
use clap::{Args, ValueEnum};

pub fn run(args: EvalArgs) -> Result<ExitCode> {
    let delta = parse_delta(&args)?;
    let mut est = trajectories::Labelled::read(&args.est)
        .with_context(|| format!("--est {}", args.est.display()))?;
    let mut gt = args.reference.read(&args.gt)?;
    trajectories::reconcile(&mut est, &mut gt)?;
    let (est, gt) = (est.trajectory, gt.trajectory);
    let opts = EvalOptions {
        reference_label: args.gt.display().to_string(),
        estimate_label: args.est.display().to_string(),
        ..EvalOptions::default()
    };
    let label = args.reference.label(&args.gt);
    let coverage = of_evaluation(&est, &gt, &opts);
    if coverage.is_low() {
        let warning = reference_args::warning(&coverage, &label, args.reference.stamp_map());
        eprintln!("warning: {warning}");
    }
    let acc = evaluate(&est, &gt, &opts)?;
    println!("{} vs {}", args.est.display(), args.gt.display());
    println!(
        "  associated poses             {:>12}",
        acc.associated_poses
    );
    print_coverage(&coverage);
    println!("  ATE RMSE (m)                 {:>12.4}", acc.ate_rmse_m);
    println!("  ATE mean (m)                 {:>12.4}", acc.ate_mean_m);
    println!(
        "  APE rot RMSE (deg)           {:>12.4}",
        acc.ate_rot_rmse_deg
    );
    if acc.alignment_roll_from_orientations {
        println!("  (nearly straight path: the alignment's roll about it is taken from the orientations)");
    }
    println!(
        "  RPE trans RMSE (m/frame)     {:>12.4}",
        acc.rpe_trans_rmse_m
    );
    println!(
        "  RPE rot RMSE (deg/frame)     {:>12.4}",
        acc.rpe_rot_rmse_deg
    );
    if let Some(d) = acc.drift_pct {
        println!("  drift (%)                    {d:>12.3}");
    }
    if let Some(delta) = delta {
        print_delta_rpe(&opts, delta, &est, &gt)?;
    }
    if args.json {
        print_json(&acc, &label, &coverage)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The accuracy as JSON, with the reference's label and the association figures added.
fn print_json(acc: &keylo::eval::Accuracy, label: &str, coverage: &Coverage) -> Result<()> {
    let doc = EvalDocument {
        accuracy: acc,
        reference_label: label,
        association: coverage,
    };
    // Through a `Value`, so the keys come out sorted as they always have.
    println!(
        "{}",
        serde_json::to_string_pretty(&serde_json::to_value(&doc)?)?
    );
    Ok(())
}

/// The association figures; the two time ranges too when fewer than 90 % associate.
fn print_coverage(c: &Coverage) {
    println!("  associated / estimated       {:>12}", c.ratio());
    if !c.is_low() {
        return;
    }
    println!("    (fewer than 90 %: see the warning on stderr)");
    println!(
        "  estimate times (s)           {}",
        range_text(c.estimate_range_s)
    );
    println!(
        "  reference times (s)          {}",
        range_text(c.reference_range_s)
    );
}

/// Checks `--delta` before any work is done.
fn parse_delta(args: &EvalArgs) -> Result<Option<Delta>> {
    let Some(delta) = args.delta else {
        return Ok(None);
    };
    Ok(Some(match args.delta_unit {
        DeltaUnit::Frames if delta >= 1.0 && delta.fract() == 0.0 && delta < 1e9 => {
            Delta::Frames(delta as usize)
        }
        DeltaUnit::Frames => bail!("--delta {delta}: a frame delta must be a whole number >= 1"),
        DeltaUnit::M if delta.is_finite() && delta > 0.0 => Delta::Meters(delta),
        DeltaUnit::M => {
            bail!("--delta {delta}: a distance delta must be a finite number of metres > 0")
        }
    }))
}

fn print_delta_rpe(
    opts: &EvalOptions,
    delta: Delta,
    est: &keylo::Trajectory,
    gt: &keylo::Trajectory,
) -> Result<()> {
    let pairs = associate_labeled(
        gt,
        &opts.reference_label,
        est,
        &opts.estimate_label,
        &AssociateOptions::default(),
    )?;
    let r = rpe(
        &pairs,
        &RpeOptions {
            delta,
            ..RpeOptions::default()
        },
    )?;
    println!(
        "  RPE trans RMSE over {delta} (m)  {:>8.4}  ({} pairs)",
        r.translation.rmse, r.translation.n
    );
    println!(
        "  RPE rot RMSE over {delta} (deg)  {:>8.4}",
        r.rotation_deg.rmse
    );
    Ok(())
}

#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Estimated trajectory (TUM or KITTI).
    #[arg(long)]
    pub est: PathBuf,
    /// Reference trajectory (TUM or KITTI).
    #[arg(long)]
    pub gt: PathBuf,
    #[command(flatten)]
    pub reference: crate::reference_args::ReferenceArgs,
    /// Also print the result as JSON.
    #[arg(long)]
    pub json: bool,
    /// An extra RPE over this delta (as `evo_rpe --delta`), e.g. `--delta 10 --delta-unit m`.
    #[arg(long)]
    pub delta: Option<f64>,
    /// Unit of --delta.
    #[arg(long, value_enum, default_value_t = DeltaUnit::Frames)]
    pub delta_unit: DeltaUnit,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DeltaUnit {
    /// Pairs `delta` frames apart.
    Frames,
    /// Pairs `delta` metres of reference path apart.
    M,
}
