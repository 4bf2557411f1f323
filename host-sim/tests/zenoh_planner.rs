//! The simulator's global planner over Zenoh (feature `zenoh`): a private `host-sim serve
//! -- --transport zenoh` is started on free ports of 127.0.0.1, plans come back identical
//! to the in-process planner's, a walled-off goal is "unreachable", a scenario runs
//! through it, dropping the planner stops the server, and `host-sim demo --planner zenoh`
//! runs.
#![cfg(feature = "zenoh")]

use host_sim::sim::mission::{self, Outcome};
use host_sim::sim::planner::{GlobalPlanRequest, GlobalPlanner, InProcess, PlanFailure};
use host_sim::sim::scenarios::{self, mission_params};
use host_sim::sim::zenoh::ZenohPlanner;
use planner_core::geometry::Cell;
use planner_core::planner::PlannerKind;
use std::path::Path;
use std::time::{Duration, Instant};

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
    let mut z = start();
    let sc = scenarios::all();
    let walled = sc.iter().find(|s| s.name == "walled-off-goal").unwrap();
    let aisle = sc.iter().find(|s| s.name == "u-turn-aisle-end").unwrap();
    let tclhho: PlannerKind = "tclhho".parse().unwrap();
    for algo in [PlannerKind::AStar, PlannerKind::Theta, tclhho] {
        let spec = aisle.mission(algo, 3).unwrap();
        let request = GlobalPlanRequest {
            start: Cell::new(3, 9),
            goal: spec.goal,
            algo,
            params: mission_params(),
            seed: 3,
        };
        z.set_map(spec.grid.view()).unwrap();
        let a = z.plan(&request).unwrap();
        let mut local = InProcess::new();
        local.set_map(spec.grid.view()).unwrap();
        let b = local.plan(&request).unwrap();
        assert_eq!(a.points, b.points, "{}", algo.name());
        assert!((a.length - b.length).abs() < 1e-4);
    }
    let spec = walled.mission(tclhho, 1).unwrap();
    z.set_map(spec.grid.view()).unwrap();
    let r = z.plan(&GlobalPlanRequest {
        start: Cell::new(1, 1),
        goal: spec.goal,
        algo: tclhho,
        params: mission_params(),
        seed: 1,
    });
    assert_eq!(r.err(), Some(PlanFailure::Unreachable));
}

#[test]
fn a_scenario_runs_over_zenoh_and_the_server_stops_with_the_planner() {
    let mut z = start();
    let pid = z.server_pid().unwrap();
    let sc = scenarios::all();
    let case = sc.iter().find(|s| s.name == "parked-robot-replan").unwrap();
    let spec = case.mission("tclhho".parse().unwrap(), 1).unwrap();
    let r = mission::run(&spec, &mut z);
    assert_eq!(r.outcome, Outcome::Arrived, "{r:?}");
    assert_eq!(r.collisions_static + r.collisions_dynamic, 0);
    assert!(r.replans >= 1);
    drop(z);
    let t0 = Instant::now();
    while Path::new(&format!("/proc/{pid}")).exists() && t0.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        !Path::new(&format!("/proc/{pid}")).exists(),
        "server {pid} still running"
    );
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
