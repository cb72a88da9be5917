//! The whole pipeline (config → simulator → KISS-ICP → evaluation) on short simulated
//! sequences, with accuracy bounds measured on these exact sequences (see
//! docs/results/accuracy-bounds.md for the measured values and the margins).

use keylo::config::RawConfig;
use keylo::eval::{evaluate, Accuracy, EvalOptions};
use keylo::{Pipeline, Trajectory};

/// Runs a TOML config to the end; returns the accuracy against the simulator's ground truth.
fn run(toml: &str) -> (Accuracy, usize) {
    let registry = keylo::registry();
    let raw = RawConfig::parse("test", toml).unwrap();
    let config = registry.resolve(&raw).unwrap();
    let mut pipeline = Pipeline::build(&config, &registry).unwrap();
    let mut est = Trajectory::default();
    let mut points = 0;
    while let Some(result) = pipeline.step() {
        let r = result.unwrap();
        est.push(r.stamp, r.pose);
        points += r.registered_points;
    }
    let gt = pipeline.source.ground_truth().unwrap();
    let acc = evaluate(&est, &gt, &EvalOptions::default()).unwrap();
    println!(
        "{toml}\n=> {acc:?}\n   mean registered points {}",
        points / est.len()
    );
    (acc, est.len())
}

#[test]
fn lab_indoor_tuning() {
    let (acc, n) = run("[source]\nscene = 'lab'\nframes = 40\n[registrar]\nmax_range = 30.0\n");
    assert_eq!(n, 40);
    assert!(acc.ate_rmse_m < 0.03, "{acc:?}");
    assert!(acc.rpe_rot_rmse_deg < 0.5, "{acc:?}");
}

#[test]
fn lab_upstream_defaults() {
    let (acc, _) = run("[source]\nscene = 'lab'\nframes = 40\n");
    assert!(acc.ate_rmse_m < 0.17, "{acc:?}");
}

#[test]
fn road_upstream_defaults() {
    let (acc, _) = run("[source]\nscene = 'road'\nframes = 40\n");
    assert!(acc.ate_rmse_m < 0.1, "{acc:?}");
    assert!(acc.rpe_trans_rmse_m < 0.1, "{acc:?}");
}

#[test]
fn corridor_is_harder_than_the_lab() {
    let (lab, _) = run("[source]\nscene = 'lab'\nframes = 40\n[registrar]\nmax_range = 30.0\n");
    let (corridor, _) =
        run("[source]\nscene = 'corridor'\nframes = 40\n[registrar]\nmax_range = 30.0\n");
    assert!(corridor.ate_rmse_m < 0.4, "{corridor:?}");
    assert!(
        corridor.ate_rmse_m > lab.ate_rmse_m,
        "corridor {corridor:?} lab {lab:?}"
    );
}

#[test]
fn voxel_downsampler_and_os1_64_run_end_to_end() {
    let (acc, n) = run("[source]\nscene = 'lab'\nframes = 30\nsensor = 'os1-64'\n\
         [downsampler]\nkind = 'voxel'\nvoxel_size = 0.1\n[registrar]\nmax_range = 30.0\n");
    assert_eq!(n, 30);
    assert!(acc.ate_rmse_m < 0.03, "{acc:?}");
}
