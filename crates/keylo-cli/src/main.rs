//! `keylo`: keypoint-assisted LiDAR odometry from the command line.

mod args;
mod cmd_config;
mod cmd_eval;
mod cmd_run;
mod cmd_sim;
mod configs;
mod report;
mod resources;

use std::process::ExitCode;

use clap::Parser;

use args::{Cli, Command};

/// Exit status for a run that stopped on a bad frame (trajectory so far is written).
pub const EXIT_FRAME_FAILED: u8 = 3;

fn main() -> ExitCode {
    let cli = Cli::parse();
    init_logging(cli.verbose, cli.quiet);
    if let Some(n) = cli.threads {
        if let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
        {
            eprintln!("error: --threads {n}: {e}");
            return ExitCode::from(2);
        }
    }
    let outcome = match cli.command {
        Command::Run(a) => cmd_run::run(a, cli.quiet),
        Command::Sim(a) => cmd_sim::run(a, cli.quiet),
        Command::Eval(a) => cmd_eval::run(a),
        Command::Config(a) => cmd_config::run(a),
    };
    match outcome {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn init_logging(verbose: u8, quiet: bool) {
    let level = match (quiet, verbose) {
        (true, _) => "error",
        (false, 0) => "warn",
        (false, 1) => "info",
        (false, 2) => "debug",
        _ => "trace",
    };
    let filter = tracing_subscriber::EnvFilter::try_from_env("KEYLO_LOG")
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_target(false)
        .init();
}
