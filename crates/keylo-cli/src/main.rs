//! `keylo`: keypoint-assisted LiDAR odometry from the command line.

mod arg_groups;
mod args;
mod atomic;
mod cloud_ply;
mod cmd_config;
mod cmd_convert;
mod cmd_eval;
mod cmd_info;
mod cmd_localise;
mod cmd_map;
mod cmd_plugins;
#[cfg(feature = "ros2")]
mod cmd_ros2;
mod cmd_run;
mod cmd_sim;
mod compare;
mod configs;
mod degeneracy_out;
mod degenerate_out;
mod interrupt;
mod journal;
mod keypoints;
mod overlay;
mod plot_out;
mod realism;
mod reference_args;
mod reference_out;
mod report;
mod report_page;
mod resources;
#[cfg(feature = "ros2")]
mod ros2_files;
mod ros2_map;
mod shard;
mod trajectories;
mod view_out;

use std::process::ExitCode;

use clap::Parser;

use args::{Cli, Command};

// Frames are large, short-lived buffers: glibc's malloc returns them to the kernel and faults
// them in again every frame (half the time of reading an Ouster frame); mimalloc keeps them.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Exit status for a run that stopped on a bad frame (trajectory so far is written).
pub const EXIT_FRAME_FAILED: u8 = 3;
/// Exit status for a run whose every frame was degenerate (too few points, or a pose direction
/// without information): its trajectory is the motion model's, not odometry. Written anyway.
pub const EXIT_DEGENERATE: u8 = 4;
/// Exit status for a run stopped by Ctrl-C (its results so far are written), as shells use.
pub const EXIT_INTERRUPTED: u8 = 130;

fn main() -> ExitCode {
    keylo::features::keep_native_heap();
    let cli = Cli::parse();
    init_logging(cli.verbose, cli.quiet);
    if let Some(n) = cli.threads {
        if n == 0 || n > 1024 {
            eprintln!("error: --threads {n}: expected 1..=1024");
            return ExitCode::from(2);
        }
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
        Command::Sim(a) => cmd_sim::run(a, cli.threads, cli.quiet),
        Command::Eval(a) => cmd_eval::run(a),
        Command::Info(a) => cmd_info::run(a),
        Command::Convert(a) => cmd_convert::run(a, cli.quiet),
        Command::Config(a) => cmd_config::run(a),
        Command::Plugins(a) => cmd_plugins::run(a),
        Command::Map(a) => cmd_map::run(a),
        Command::Localise(a) => cmd_localise::run(a, cli.quiet),
        Command::Compare(a) => compare::run(a, cli.threads, cli.quiet),
        Command::Report(a) => report_page::run(a, cli.quiet),
        Command::Keypoints(a) => keypoints::run(a, cli.threads, cli.quiet),
        #[cfg(feature = "ros2")]
        Command::Ros2(a) => cmd_ros2::run(a, cli.quiet),
    };
    match outcome {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", error_chain(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes joined by ": ", leaving out a cause whose text the message
/// already holds (library errors often print their source themselves).
pub fn error_chain(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let part = cause.to_string();
        if !text.contains(&part) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&part);
        }
    }
    text
}

fn init_logging(verbose: u8, quiet: bool) {
    let level = match (quiet, verbose) {
        (true, _) => "error",
        (false, 0) => "warn",
        (false, 1) => "info",
        (false, 2) => "debug",
        _ => "trace",
    };
    // RustDDS and ros2-client (`keylo ros2`) log protocol details at info and the ROS
    // distribution they were built for at warn: their warnings and errors only, unless
    // KEYLO_LOG asks for them. The live view's server (`--view`) says at error level that a
    // viewer went away without closing: not the run's error, shown from -v on.
    let viewers = if quiet || verbose == 0 { "off" } else { level };
    let filter = tracing_subscriber::EnvFilter::try_from_env("KEYLO_LOG").unwrap_or_else(|_| {
        tracing_subscriber::EnvFilter::new(format!(
            "{level},rustdds=warn,ros2_client=error,\
             foxglove::websocket::connected_client::poller={viewers}"
        ))
    });
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_target(false)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .init();
}
