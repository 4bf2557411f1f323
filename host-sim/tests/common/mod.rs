//! Checks shared by the simulator's service planners (`ipc_planner`, `zenoh_planner`).

use host_sim::sim::mission::{self, Outcome};
use host_sim::sim::planner::{GlobalPlanRequest, GlobalPlanner, InProcess, PlanFailure};
use host_sim::sim::scenarios::{self, mission_params};
use planner_core::geometry::Cell;
use planner_core::planner::{Blend, PlanParams, PlannerKind};
use std::path::Path;
use std::time::{Duration, Instant};

/// `planner` plans as the in-process planner does (A*, Theta*, TCLHHO by length and
/// blended: the request carries the blend), and a walled-off goal is `Unreachable`.
pub fn matches_in_process_and_walls_are_unreachable(planner: &mut dyn GlobalPlanner) {
    let sc = scenarios::all();
    let walled = sc.iter().find(|s| s.name == "walled-off-goal").unwrap();
    let aisle = sc.iter().find(|s| s.name == "u-turn-aisle-end").unwrap();
    let tclhho: PlannerKind = "tclhho".parse().unwrap();
    let blended = PlanParams {
        blend: Blend {
            clearance: 0.45,
            clearance_weight: 16.0,
            turn_weight: 1.0,
        },
        ..mission_params()
    };
    for (algo, params) in [
        (PlannerKind::AStar, mission_params()),
        (PlannerKind::Theta, mission_params()),
        (tclhho, mission_params()),
        (tclhho, blended),
    ] {
        let spec = aisle.mission(algo, 3).unwrap();
        let request = GlobalPlanRequest {
            start: Cell::new(3, 9),
            goal: spec.goal,
            algo,
            params,
            seed: 3,
        };
        planner.set_map(spec.grid.view()).unwrap();
        let a = planner.plan(&request).unwrap();
        let mut local = InProcess::new();
        local.set_map(spec.grid.view()).unwrap();
        let b = local.plan(&request).unwrap();
        assert_eq!(a.points, b.points, "{} {:?}", algo.name(), params.blend);
        assert!((a.length - b.length).abs() < 1e-4);
        assert!(a.length > 15.0, "round the shelf end: {}", a.length);
    }
    let spec = walled.mission(tclhho, 1).unwrap();
    planner.set_map(spec.grid.view()).unwrap();
    let r = planner.plan(&GlobalPlanRequest {
        start: Cell::new(1, 1),
        goal: spec.goal,
        algo: tclhho,
        params: mission_params(),
        seed: 1,
    });
    assert_eq!(r.err(), Some(PlanFailure::Unreachable));
}

/// The parked-robot scenario arrives through `planner` (replanning at least once), and
/// dropping `planner` stops its server `pid` within 5 s.
pub fn runs_a_scenario_then_stops_its_server<P: GlobalPlanner>(mut planner: P, pid: u32) {
    assert!(Path::new(&format!("/proc/{pid}")).exists());
    let sc = scenarios::all();
    let case = sc.iter().find(|s| s.name == "parked-robot-replan").unwrap();
    let spec = case.mission("tclhho".parse().unwrap(), 1).unwrap();
    let r = mission::run(&spec, &mut planner);
    assert_eq!(r.outcome, Outcome::Arrived, "{r:?}");
    assert_eq!(r.collisions_static + r.collisions_dynamic, 0);
    assert!(r.replans >= 1);
    drop(planner);
    let t0 = Instant::now();
    while Path::new(&format!("/proc/{pid}")).exists() && t0.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        !Path::new(&format!("/proc/{pid}")).exists(),
        "server {pid} still running"
    );
}
