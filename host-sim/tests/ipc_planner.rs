//! The simulator's global planner over iceoryx2: a private `host-sim serve` is started, maps
//! are uploaded, plans come back identical to the in-process planner's, a walled-off goal is
//! "unreachable", a whole scenario runs through it, and dropping the planner stops the server.

mod common;

use host_sim::sim::ipc::IpcPlanner;
use std::path::Path;

fn start() -> IpcPlanner {
    let p = IpcPlanner::start_with(Path::new(env!("CARGO_BIN_EXE_host-sim")), None)
        .expect("start a private planner-server");
    assert!(p.started_server());
    assert!(p.prefix().starts_with("host-sim-"));
    p
}

#[test]
fn plans_over_ipc_match_in_process_and_walls_are_unreachable() {
    common::matches_in_process_and_walls_are_unreachable(&mut start());
}

#[test]
fn a_scenario_runs_over_ipc_and_the_server_stops_with_the_planner() {
    let planner = start();
    let pid = planner.server_pid().unwrap();
    common::runs_a_scenario_then_stops_its_server(planner, pid);
}
