//! `keylo ros2`'s settings: a wrong `[ros2]` key or value stops the node before it joins DDS,
//! naming the key; `keylo run` carries a `[ros2]` table through, so one config serves both.
//! (The node itself is tested against Cyclone DDS in a private network namespace:
//! scripts/ros2/interop-test.sh; nothing here opens a DDS participant or a socket.)
#![cfg(feature = "ros2")]

mod common;

use common::{expect_failure, keylo, small_sim};

#[test]
fn bad_ros2_settings_name_the_key_before_any_dds() {
    let tmp = tempfile::tempdir().unwrap();
    let cases = [
        ("ros2.points_topc=/x", "points_topc"),
        ("ros2.base_to_lidar=[0,0,0,0,0,0,2]", "base_to_lidar"),
        ("ros2.base_to_lidar=[0,0,0]", "expected 7"),
        ("ros2.max_pending_clouds=0", "max_pending_clouds"),
        ("ros2.residual_sigma_m=-1", "residual_sigma_m"),
        ("ros2.input_reliability=\"sometimes\"", "input_reliability"),
        ("ros2.domain_id=70000", "domain_id"),
    ];
    for (set, needle) in cases {
        let o = keylo(&["ros2", "--set", set], tmp.path());
        expect_failure(&o, 2, needle);
        assert!(
            common::stderr(&o).contains("ros2."),
            "{set}: {}",
            common::stderr(&o)
        );
    }
}

#[test]
fn keylo_run_carries_a_ros2_table_through() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("sim");
    small_sim(&data, 3);
    let config = tmp.path().join("node.toml");
    std::fs::write(
        &config,
        "[registrar]\nkind = \"kiss-icp\"\n\n[ros2]\npoints_topic = \"/ouster/points\"\n",
    )
    .unwrap();
    let out = tmp.path().join("run");
    let o = keylo(
        &[
            "-q",
            "run",
            config.to_str().unwrap(),
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let resolved = std::fs::read_to_string(out.join("config.toml")).unwrap();
    assert!(
        resolved.contains("[ros2]") && resolved.contains("/ouster/points"),
        "{resolved}"
    );
}
