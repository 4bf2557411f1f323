//! `host-sim soak` with the robot's safety profile (issue 22): a static margin of 0.1 m from
//! shelves and a protective field (stop within 0.25 m, full speed beyond 1.25 m of people and
//! robots in front). Twenty missions with people and robots arrive with no contact while the
//! robot moves and never closer to a shelf than half the margin; the same mission without
//! the profile (seed 129) runs into someone, which is what the profile is for.

use serde_json::Value;
use std::process::{Command, Output};

fn soak(tag: &str, args: &[&str]) -> (Output, Value) {
    let out = std::env::temp_dir().join(format!("safety-soak-{tag}-{}", std::process::id()));
    let output = Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .arg("soak")
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let text = std::fs::read_to_string(out.join("report.json")).unwrap_or_default();
    let report = serde_json::from_str(&text).unwrap_or(Value::Null);
    let _ = std::fs::remove_dir_all(&out);
    (output, report)
}

#[test]
fn missions_keep_the_margin_and_touch_nobody_while_moving() {
    let (output, r) = soak("amr", &["--seed", "120", "--missions", "20"]);
    let why = format!("{r}\n{}", String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{why}");
    assert_eq!(r["success"], 20, "{why}");
    assert_eq!(r["collisions_static"], 0, "{why}");
    assert_eq!(r["contacts_moving"], 0, "{why}");
    let min = r["min_clearance_static"].as_f64().unwrap();
    assert!(min >= 0.05, "min static clearance {min}: {why}");
    assert_eq!(r["safety"]["shelf_margin"].as_f64().unwrap() as f32, 0.1);
}

#[test]
fn without_the_profile_the_same_kind_of_mission_touches_someone() {
    let (output, r) = soak(
        "none",
        &[
            "--seed",
            "129",
            "--missions",
            "1",
            "--shelf-margin",
            "0",
            "--field-stop",
            "0",
            "--field-slow",
            "0",
            "--min-success",
            "0",
        ],
    );
    let why = format!("{r}\n{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(output.status.code(), Some(3), "{why}");
    assert!(r["contacts_moving"].as_u64().unwrap() >= 1, "{why}");
    assert!(r["min_clearance_static"].as_f64().unwrap() < 0.05, "{why}");
    let (output, r) = soak("seed-129", &["--seed", "129", "--missions", "1"]);
    assert!(output.status.success(), "{r}");
    assert_eq!(r["contacts_moving"], 0, "{r}");
}

#[test]
fn a_bad_safety_figure_is_named_and_exits_2() {
    let (output, _) = soak("bad", &["--missions", "1", "--field-slow", "0.1"]);
    assert_eq!(output.status.code(), Some(2));
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(
        err.contains("--field-slow 0.1: must be at least --field-stop"),
        "{err}"
    );
}
