//! keylo's GICP alignment against PCL 1.13's on the same clouds from the same guess
//! (`tests/fixtures/gicp/pcl_golden.txt`, made by PCL; see its README): within 5 mm and 0.1°
//! on the simulated lab and road pairs, where PCL's own result is stable.

use keylo_registration::gicp::{align, GicpCloud, GicpSettings};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

mod common;

use common::{fixtures, load_bin as load};

fn golden(case: &str) -> Isometry3<f64> {
    let text = std::fs::read_to_string(fixtures().join("gicp/pcl_golden.txt")).unwrap();
    let line = text.lines().find(|l| l.starts_with(case)).unwrap();
    let v: Vec<f64> = line
        .split_whitespace()
        .skip(1)
        .take(7)
        .map(|x| x.parse().unwrap())
        .collect();
    Isometry3::from_parts(
        Translation3::new(v[0], v[1], v[2]),
        UnitQuaternion::from_quaternion(Quaternion::new(v[6], v[3], v[4], v[5])),
    )
}

#[test]
fn gicp_equals_pcl_on_the_stable_pairs() {
    for case in ["lab", "road"] {
        let dir = fixtures().join("ndt");
        let source =
            GicpCloud::new(load(&dir.join(format!("{case}_source.bin"))), 20, 1e-3).unwrap();
        let target =
            GicpCloud::new(load(&dir.join(format!("{case}_target.bin"))), 20, 1e-3).unwrap();
        let r = align(
            (&source.cloud.points, &source.patches),
            &target,
            &Isometry3::identity(),
            &GicpSettings::default(),
        )
        .unwrap();
        let d = golden(case).inverse() * r.pose;
        let (t, deg) = (d.translation.vector.norm(), d.rotation.angle().to_degrees());
        println!(
            "{case}: {:.2} mm, {deg:.4}° from PCL in {} iterations",
            1e3 * t,
            r.iterations
        );
        assert!(t < 5e-3 && deg < 0.1, "{case}: {t} m, {deg}° from PCL");
    }
}
