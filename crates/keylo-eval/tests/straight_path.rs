//! On a straight path evo's positions-only alignment picks its roll from noise (173.8° rotation
//! error on `tests/fixtures/evo/straight/`); keylo takes that roll from the orientations.

use keylo_eval::align::{positions, umeyama};
use keylo_eval::ape::{ape, ape_errors, ApeOptions};
use keylo_eval::associate::Associated;
use keylo_eval::pose_error::PoseRelation;
use keylo_io::trajectory::read_trajectory;

const DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/fixtures/evo/straight/"
);

fn rmse(v: &[f64]) -> f64 {
    (v.iter().map(|e| e * e).sum::<f64>() / v.len() as f64).sqrt()
}

#[test]
fn a_straight_path_gets_its_roll_from_the_orientations() {
    let gt = read_trajectory(format!("{DIR}corridor_gt.tum")).unwrap();
    let est = read_trajectory(format!("{DIR}corridor_superpoint_est.tum")).unwrap();
    let pairs = Associated::by_index(&gt, &est).unwrap();

    // evo's alignment (positions only) and its numbers, from the README.
    let evo = umeyama(
        &positions(&pairs.estimate),
        &positions(&pairs.reference),
        false,
    )
    .unwrap();
    let evo_aligned = evo.apply_trajectory(&pairs.estimate);
    let evo_rot = rmse(&ape_errors(
        &pairs.reference,
        &evo_aligned,
        PoseRelation::AngleDeg,
    ));
    let evo_trans = rmse(&ape_errors(
        &pairs.reference,
        &evo_aligned,
        PoseRelation::Translation,
    ));
    assert!((evo_rot - 173.831638).abs() < 1e-3, "{evo_rot}");
    assert!((evo_trans - 0.077874).abs() < 1e-5, "{evo_trans}");

    let ours = ape(&pairs, &ApeOptions::default()).unwrap();
    assert!(ours.alignment.roll_from_orientations);
    assert!(ours.rotation_deg.rmse < 1.0, "{}", ours.rotation_deg.rmse);
    // The positions barely care about that roll: the translation error hardly moves.
    assert!(
        (ours.translation.rmse - evo_trans).abs() < 0.01,
        "{}",
        ours.translation.rmse
    );
}
