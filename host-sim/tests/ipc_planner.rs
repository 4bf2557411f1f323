//! The simulator's global planner over iceoryx2: a private `host-sim serve` is started, maps
//! are uploaded, plans come back identical to the in-process planner's, a walled-off goal is
//! "unreachable", a whole scenario runs through it, and dropping the planner stops the server.

use host_sim::sim::ipc::IpcPlanner;
use host_sim::sim::mission::{self, Outcome};
use host_sim::sim::planner::{GlobalPlanRequest, GlobalPlanner, InProcess, PlanFailure};
use host_sim::sim::scenarios::{self, mission_params};
use planner_core::geometry::Cell;
use planner_core::planner::PlannerKind;
use std::path::Path;
use std::time::{Duration, Instant};

fn start() -> IpcPlanner {
    let p = IpcPlanner::start_with(Path::new(env!("CARGO_BIN_EXE_host-sim")), None)
        .expect("start a private planner-server");
    assert!(p.started_server());
    assert!(p.prefix().starts_with("host-sim-"));
    p
}

#[test]
fn plans_over_ipc_match_in_process_and_walls_are_unreachable() {
    let mut ipc = start();
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
        ipc.set_map(spec.grid.view()).unwrap();
        let a = ipc.plan(&request).unwrap();
        let mut local = InProcess::new();
        local.set_map(spec.grid.view()).unwrap();
        let b = local.plan(&request).unwrap();
        assert_eq!(a.points, b.points, "{}", algo.name());
        assert!((a.length - b.length).abs() < 1e-4);
        assert!(a.length > 15.0, "round the shelf end: {}", a.length);
    }
    let spec = walled.mission(tclhho, 1).unwrap();
    ipc.set_map(spec.grid.view()).unwrap();
    let r = ipc.plan(&GlobalPlanRequest {
        start: Cell::new(1, 1),
        goal: spec.goal,
        algo: tclhho,
        params: mission_params(),
        seed: 1,
    });
    assert_eq!(r.err(), Some(PlanFailure::Unreachable));
}

#[test]
fn a_scenario_runs_over_ipc_and_the_server_stops_with_the_planner() {
    let mut ipc = start();
    let pid = ipc.server_pid().unwrap();
    assert!(Path::new(&format!("/proc/{pid}")).exists());
    let sc = scenarios::all();
    let case = sc.iter().find(|s| s.name == "parked-robot-replan").unwrap();
    let spec = case.mission("tclhho".parse().unwrap(), 1).unwrap();
    let r = mission::run(&spec, &mut ipc);
    assert_eq!(r.outcome, Outcome::Arrived, "{r:?}");
    assert_eq!(r.collisions_static + r.collisions_dynamic, 0);
    assert!(r.replans >= 1);
    drop(ipc);
    let t0 = Instant::now();
    while Path::new(&format!("/proc/{pid}")).exists() && t0.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        !Path::new(&format!("/proc/{pid}")).exists(),
        "server {pid} still running"
    );
}
