//! `keylo keypoints sweep`: Algorithm 1 of the paper, resumable, with the optimum per metric
//! and overall, tables by interpolation and by resolution, and heat maps.

use std::process::ExitCode;

use anyhow::Result;
use keylo::kpeval::sweep::{parse_interpolation, parse_sizes, run_sweep, SweepGrid, SweepOptions};
use keylo::BuildContext;

use super::eval::progress;
use super::sweep_report::{write_report, SweepReport};
use super::{input, SweepArgs};

pub fn run(args: SweepArgs, threads: Option<usize>, quiet: bool) -> Result<ExitCode> {
    let spec = input::spec(&args.input)?;
    let grid = SweepGrid {
        interpolations: args
            .interpolations
            .split(',')
            .map(parse_interpolation)
            .collect::<Result<_, _>>()?,
        widths: parse_sizes(&args.widths, "--widths")?,
        heights: parse_sizes(&args.heights, "--heights")?,
    };
    let prepared = input::prepare(&args.input, &spec, threads)?;
    let bar = progress(quiet, "sweeping");
    let tick = |done: usize, total: usize, resumed: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        if resumed > 0 {
            bar.set_message(format!("({resumed} resumed)"));
        }
    };
    if let Some(shard) = args.input.shard {
        let code =
            super::shards::sweep_shard(&args, shard, (&spec, &grid), &prepared, quiet, &tick);
        bar.finish_and_clear();
        return code;
    }
    let input::Prepared {
        registry,
        set,
        combos,
        planes,
        jobs,
    } = prepared;
    let out = args.input.out();
    let result = run_sweep(
        &planes,
        &combos,
        &spec,
        &grid,
        &registry,
        &BuildContext {
            trust: args.input.trust.trust(),
            ..BuildContext::default()
        },
        &SweepOptions {
            jobs,
            skip_unavailable: set.skips_unavailable(),
            store: out.join("sweep.csv"),
            progress: Some(&tick),
            only: None,
            timed: None,
        },
    )?;
    bar.finish_and_clear();
    write_report(
        out,
        &SweepReport {
            grid: &grid,
            spec: &spec,
            images: planes.len(),
            jobs,
            result: &result,
        },
        args.input.no_plots,
        quiet,
    )
}
