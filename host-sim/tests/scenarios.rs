//! The simulator's hard cases (issue 6): each must end at the goal with zero collisions, or
//! with the planner's "unreachable" outcome where the goal is walled off. The same cases run
//! from the CLI as `host-sim scenarios` (with pictures).

use host_sim::sim::mission::{self, MissionResult, Outcome};
use host_sim::sim::planner::InProcess;
use host_sim::sim::scenarios::{self, Expect};
use planner_core::planner::PlannerKind;

fn run(name: &str) -> MissionResult {
    let all = scenarios::all();
    let sc = all
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no scenario {name}"));
    let algo: PlannerKind = "tclhho".parse().unwrap();
    let spec = sc.mission(algo, 1).unwrap();
    let r = mission::run(&spec, &mut InProcess::new());
    let summary = format!(
        "{name}: {:?}, {} static + {} dynamic collisions, t = {:?}, replans {}, stuck {}, min clearance {:.3}",
        r.outcome,
        r.collisions_static,
        r.collisions_dynamic,
        r.time_to_goal,
        r.replans,
        r.stuck_events,
        r.min_clearance_static
    );
    match sc.expect {
        Expect::Arrive => {
            assert_eq!(r.outcome, Outcome::Arrived, "{summary}");
            assert_eq!(r.collisions_static, 0, "{summary}");
            assert_eq!(r.collisions_dynamic, 0, "{summary}");
            assert!(r.success, "{summary}");
            // It drove: the trajectory ends within the goal tolerance of the goal cell.
            let end = *r.trajectory.last().unwrap();
            assert!(
                end.distance(spec.goal.center()) <= 0.35,
                "{summary}: ends at {end:?}"
            );
            assert!(r.min_clearance_static >= 0.0, "{summary}");
        }
        Expect::Unreachable => {
            assert_eq!(r.outcome, Outcome::Unreachable, "{summary}");
            assert!(!r.success);
            assert_eq!(r.driven_length, 0.0, "{summary}");
        }
    }
    println!("{summary}");
    r
}

#[test]
fn obstacle_dead_ahead() {
    let r = run("obstacle-ahead");
    // The pallet is not on the map: the robot had to get round it, so it came within a few
    // cells of it and did not drive through it.
    let d = r.min_clearance_dynamic.expect("an obstacle was present");
    assert!((0.0..2.0).contains(&d), "min dynamic clearance {d}");
}

#[test]
fn one_cell_aisle() {
    let r = run("one-cell-aisle");
    // Through a one-cell aisle the footprint (radius 0.3) has 0.2 cells to spare at best.
    assert!(r.min_clearance_static <= 0.2 + 1e-3);
}

#[test]
fn parked_robot_blocks_the_path_and_the_robot_replans() {
    let r = run("parked-robot-replan");
    assert!(r.replans >= 1, "no replan");
    assert!(
        r.plans.iter().any(|p| p.reason != "initial"),
        "{:?}",
        r.plans
    );
    // The detour through the other aisle is much longer than the blocked straight path.
    assert!(r.driven_length > 1.5 * r.planned_length);
}

#[test]
fn goal_behind_the_robot() {
    run("goal-behind");
}

#[test]
fn u_turn_at_an_aisle_end() {
    run("u-turn-aisle-end");
}

#[test]
fn person_crossing_the_aisle() {
    let r = run("person-crossing");
    assert!(r.min_clearance_dynamic.is_some());
}

#[test]
fn walled_off_goal_is_unreachable() {
    run("walled-off-goal");
}

#[test]
fn every_scenario_has_a_test() {
    let names: Vec<&str> = scenarios::all().iter().map(|s| s.name).collect();
    assert_eq!(
        names,
        [
            "obstacle-ahead",
            "one-cell-aisle",
            "parked-robot-replan",
            "goal-behind",
            "u-turn-aisle-end",
            "person-crossing",
            "walled-off-goal"
        ]
    );
}
