//! Parity with evo 1.38.1: every case of `tests/fixtures/evo/expected.json` (produced by
//! `tests/fixtures/evo/make_fixtures.sh`) is recomputed here from the command line it records.

use keylo_eval::ape::{ape, AlignMode, ApeOptions};
use keylo_eval::associate::{associate, AssociateOptions, Associated};
use keylo_eval::rpe::{rpe, Delta, RpeOptions};
use keylo_eval::stats::Stats;
use keylo_io::trajectory::read_trajectory;
use serde_json::Value;

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/fixtures/evo/");
// Observed worst case is ~6e-12 (floating-point summation order); 1e-9 leaves margin.
const REL_TOL: f64 = 1e-9;

/// An evo command line, parsed.
struct Case {
    tool: String,
    format: String,
    reference: String,
    estimate: String,
    align: AlignMode,
    angle: bool,
    associate: AssociateOptions,
    rpe: RpeOptions,
}

fn parse_command(command: &str) -> Case {
    let words: Vec<&str> = command.split_whitespace().collect();
    let mut case = Case {
        tool: words[0].to_string(),
        format: words[1].to_string(),
        reference: words[2].to_string(),
        estimate: words[3].to_string(),
        align: AlignMode::None,
        angle: false,
        associate: AssociateOptions::default(),
        rpe: RpeOptions::default(),
    };
    let (mut delta, mut unit) = (1.0, "f");
    let mut rest = words[4..].iter();
    while let Some(&flag) = rest.next() {
        let mut value = || *rest.next().unwrap();
        match flag {
            "-a" => case.align = AlignMode::Se3,
            "-as" => case.align = AlignMode::Sim3,
            "--pose_relation" => case.angle = value() == "angle_deg",
            "--delta" => delta = value().parse().unwrap(),
            "--delta_unit" => unit = value(),
            "--t_offset" => case.associate.offset = value().parse().unwrap(),
            "--t_max_diff" => case.associate.max_diff = value().parse().unwrap(),
            "--all_pairs" => case.rpe.all_pairs = true,
            "--pairs_from_reference" => case.rpe.pairs_from_reference = true,
            other => panic!("flag {other} is not mapped in this test"),
        }
    }
    case.rpe.delta = match unit {
        "f" => Delta::Frames(delta as usize),
        "m" => Delta::Meters(delta),
        other => panic!("delta unit {other} is not mapped in this test"),
    };
    case
}

fn our_stats(case: &Case) -> Stats {
    let reference = read_trajectory(format!("{DIR}{}", case.reference)).unwrap();
    let estimate = read_trajectory(format!("{DIR}{}", case.estimate)).unwrap();
    let pairs = match case.format.as_str() {
        "tum" => associate(&reference, &estimate, &case.associate).unwrap(),
        "kitti" => Associated::by_index(&reference, &estimate).unwrap(),
        other => panic!("format {other}"),
    };
    match case.tool.as_str() {
        "evo_ape" => {
            let r = ape(&pairs, &ApeOptions { align: case.align }).unwrap();
            if case.angle {
                r.rotation_deg
            } else {
                r.translation
            }
        }
        "evo_rpe" => {
            assert_eq!(case.align, AlignMode::None, "RPE cases are unaligned");
            let r = rpe(&pairs, &case.rpe).unwrap();
            if case.angle {
                r.rotation_deg
            } else {
                r.translation
            }
        }
        other => panic!("tool {other}"),
    }
}

fn check(name: &str, field: &str, ours: f64, evo: f64) -> Option<String> {
    let err = (ours - evo).abs() / evo.abs().max(1e-12);
    (err > REL_TOL)
        .then(|| format!("{name}.{field}: ours {ours:.12e} evo {evo:.12e} (rel {err:.1e})"))
}

#[test]
fn matches_evo_statistics() {
    let text = std::fs::read_to_string(format!("{DIR}expected.json")).unwrap();
    let doc: Value = serde_json::from_str(&text).unwrap();
    let cases = doc["cases"].as_array().unwrap();
    assert!(cases.len() >= 20);
    let mut failures = Vec::new();
    for c in cases {
        let name = c["name"].as_str().unwrap();
        let ours = our_stats(&parse_command(c["command"].as_str().unwrap()));
        let evo = &c["stats"];
        assert_eq!(
            ours.n as u64,
            evo["n"].as_u64().unwrap(),
            "{name}: number of errors"
        );
        let fields = [
            ("rmse", ours.rmse),
            ("mean", ours.mean),
            ("median", ours.median),
            ("std", ours.std),
            ("min", ours.min),
            ("max", ours.max),
            ("sse", ours.sse),
        ];
        for (field, value) in fields {
            failures.extend(check(name, field, value, evo[field].as_f64().unwrap()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn evo_rmse(doc: &Value, name: &str) -> f64 {
    let cases = doc["cases"].as_array().unwrap();
    let case = cases.iter().find(|c| c["name"] == name).unwrap();
    case["stats"]["rmse"].as_f64().unwrap()
}

#[test]
fn evaluate_summary_matches_evo() {
    let text = std::fs::read_to_string(format!("{DIR}expected.json")).unwrap();
    let doc: Value = serde_json::from_str(&text).unwrap();
    let gt = read_trajectory(format!("{DIR}smooth_gt.tum")).unwrap();
    let est = read_trajectory(format!("{DIR}smooth_est.tum")).unwrap();
    let acc = keylo_eval::evaluate(&est, &gt, &Default::default()).unwrap();
    assert_eq!(acc.associated_poses, 48);
    let pairs = [
        (acc.ate_rmse_m, "smooth_ape_trans"),
        (acc.ate_rot_rmse_deg, "smooth_ape_angle"),
        (acc.rpe_trans_rmse_m, "smooth_rpe_trans"),
        (acc.rpe_rot_rmse_deg, "smooth_rpe_angle"),
    ];
    for (ours, name) in pairs {
        assert!(
            check(name, "rmse", ours, evo_rmse(&doc, name)).is_none(),
            "{name}: {ours}"
        );
    }
    let drift = acc.drift_pct.unwrap();
    assert!(drift > 0.0 && drift < 10.0, "drift {drift} %");
}
