//! The simulator's global planner over Zenoh (feature `zenoh`): a private `host-sim serve
//! -- --transport zenoh` is started on free ports of 127.0.0.1, plans come back identical
//! to the in-process planner's, a walled-off goal is "unreachable", a scenario runs
//! through it, dropping the planner stops the server, and `host-sim demo --planner zenoh`
//! runs.
#![cfg(feature = "zenoh")]

mod common;

use host_sim::sim::zenoh::ZenohPlanner;
use std::path::Path;

fn start() -> ZenohPlanner {
    let p = ZenohPlanner::start_with(Path::new(env!("CARGO_BIN_EXE_host-sim")), None)
        .expect("start a private planner-server over Zenoh");
    assert!(p.started_server());
    assert!(p.prefix().starts_with("host-sim-"));
    assert!(p.endpoint().starts_with("tcp/127.0.0.1:"));
    p
}

#[test]
fn plans_over_zenoh_match_in_process_and_walls_are_unreachable() {
    common::matches_in_process_and_walls_are_unreachable(&mut start());
}

#[test]
fn a_scenario_runs_over_zenoh_and_the_server_stops_with_the_planner() {
    let planner = start();
    let pid = planner.server_pid().unwrap();
    common::runs_a_scenario_then_stops_its_server(planner, pid);
}

/// `host-sim demo --planner zenoh`: the demo mission over Zenoh (a planner alive at
/// tcp/127.0.0.1:7447 under the prefix `planner` is used, else a private one started).
#[test]
fn demo_runs_over_zenoh() {
    let out = std::env::temp_dir().join(format!("host-sim-zenoh-demo-{}", std::process::id()));
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(["demo", "--planner", "zenoh", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(stdout.contains("over Zenoh"), "{stdout}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["planner"], "zenoh", "{report}");
    let _ = std::fs::remove_dir_all(&out);
}
