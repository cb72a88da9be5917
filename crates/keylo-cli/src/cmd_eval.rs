//! `keylo eval`: ATE/RPE of one trajectory against another.

use std::process::ExitCode;

use anyhow::{Context, Result};

use crate::args::EvalArgs;

pub fn run(args: EvalArgs) -> Result<ExitCode> {
    let est = keylo::eval::io::read_trajectory(&args.est)
        .with_context(|| format!("--est {}", args.est.display()))?;
    let gt = keylo::eval::io::read_trajectory(&args.gt)
        .with_context(|| format!("--gt {}", args.gt.display()))?;
    let acc = keylo::eval::evaluate(&est, &gt, &keylo::eval::EvalOptions::default())?;
    println!("{} vs {}", args.est.display(), args.gt.display());
    println!(
        "  associated poses             {:>12}",
        acc.associated_poses
    );
    println!("  ATE RMSE (m)                 {:>12.4}", acc.ate_rmse_m);
    println!("  ATE mean (m)                 {:>12.4}", acc.ate_mean_m);
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
    if args.json {
        println!("{}", serde_json::to_string_pretty(&acc)?);
    }
    Ok(ExitCode::SUCCESS)
}
