//! The hard cases of the simulator (`host-sim scenarios`, `tests/scenarios.rs`).

use super::kinematics::DiffDrive;
use super::mission::{MissionSpec, Outcome};
use super::safety::Safety;
use super::world::{Agent, Behaviour, Kind};
use planner_core::dwa::{DwaConfig, DwaState};
use planner_core::geometry::{Cell, Point};
use planner_core::grid::GridBuf;
use planner_core::optim::any::AlgorithmKind;
use planner_core::planner::{PlanParams, PlannerKind};
use std::f32::consts::{FRAC_PI_2, PI};

/// What a scenario must end with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expect {
    /// At the goal, no collision.
    Arrive,
    /// The planner reports the goal walled off.
    Unreachable,
}

/// A scenario.
pub struct Scenario {
    /// Short name (`--case`).
    pub name: &'static str,
    /// What it tests.
    pub what: &'static str,
    /// The expected outcome.
    pub expect: Expect,
    rows: &'static [&'static str],
    start: (u16, u16, f32),
    goal: (u16, u16),
    agents: fn() -> Vec<Agent>,
}

impl Scenario {
    /// Whether `outcome` (with the collision counts) passes.
    pub fn passes(&self, outcome: &Outcome, collisions: u32) -> bool {
        match self.expect {
            Expect::Arrive => *outcome == Outcome::Arrived && collisions == 0,
            Expect::Unreachable => *outcome == Outcome::Unreachable,
        }
    }

    /// The mission of this scenario.
    pub fn mission(&self, algo: PlannerKind, seed: u64) -> anyhow::Result<MissionSpec> {
        let text = self.rows.join("\n");
        let grid = GridBuf::parse_rows(text.as_bytes()).map_err(anyhow::Error::msg)?;
        Ok(MissionSpec {
            name: self.name.to_string(),
            grid,
            plan_grid: None,
            metres_per_cell: 1.0,
            start: DwaState {
                x: self.start.0 as f32,
                y: self.start.1 as f32,
                theta: self.start.2,
                v: 0.0,
                w: 0.0,
            },
            goal: Cell::new(self.goal.0, self.goal.1),
            algo,
            params: mission_params(),
            seed,
            agents: (self.agents)(),
            people: 0,
            robots: 0,
            dwa: Safety::AMR.apply(DwaConfig::default(), 1.0),
            drive: DiffDrive::default(),
            time_limit: Some(120.0),
            record: true,
        })
    }
}

/// Swarm settings for missions: the papers' population, a short horizon with early stop
/// (replans must be quick).
///
/// The corridor's guide is the A* route (the core's default; the service gets it from the
/// request): the scenario and soak figures were measured with it.
pub fn mission_params() -> PlanParams {
    PlanParams {
        iterations: 150,
        stagnation: Some(30),
        ..PlanParams::new(AlgorithmKind::Tclhho)
    }
}

fn none() -> Vec<Agent> {
    Vec::new()
}

/// Every scenario.
pub fn all() -> Vec<Scenario> {
    vec![
        Scenario {
            name: "obstacle-ahead",
            what: "a pallet (not on the map) dead ahead on the global path",
            expect: Expect::Arrive,
            rows: &[
                "....................",
                "....................",
                "....................",
                "....................",
                "....................",
                "....................",
                "....................",
            ],
            start: (1, 3, 0.0),
            goal: (18, 3),
            agents: || {
                vec![Agent::new(
                    Kind::Parked,
                    Behaviour::Still,
                    vec![Point::new(9.0, 3.0)],
                    0.0,
                )]
            },
        },
        Scenario {
            name: "one-cell-aisle",
            what: "the only way is an aisle one cell wide (0.2 cells to spare each side)",
            expect: Expect::Arrive,
            rows: &[
                "....................",
                "....................",
                "@@@@@@@@.@@@@@@@@@@@",
                "@@@@@@@@.@@@@@@@@@@@",
                "@@@@@@@@.@@@@@@@@@@@",
                "@@@@@@@@.@@@@@@@@@@@",
                "@@@@@@@@.@@@@@@@@@@@",
                "@@@@@@@@.@@@@@@@@@@@",
                "@@@@@@@@.@@@@@@@@@@@",
                "@@@@@@@@.@@@@@@@@@@@",
                "....................",
                "....................",
            ],
            start: (2, 0, 0.0),
            goal: (17, 11),
            agents: none,
        },
        Scenario {
            name: "parked-robot-replan",
            what: "a parked robot blocks the one-cell aisle of the global path: replan via the other",
            expect: Expect::Arrive,
            rows: &[
                "....................",
                "....................",
                "@@@@@.@@@@@@@@.@@@@@",
                "@@@@@.@@@@@@@@.@@@@@",
                "@@@@@.@@@@@@@@.@@@@@",
                "@@@@@.@@@@@@@@.@@@@@",
                "@@@@@.@@@@@@@@.@@@@@",
                "@@@@@.@@@@@@@@.@@@@@",
                "@@@@@.@@@@@@@@.@@@@@",
                "@@@@@.@@@@@@@@.@@@@@",
                "....................",
                "....................",
            ],
            start: (5, 0, FRAC_PI_2),
            goal: (5, 11),
            agents: || {
                vec![Agent::new(
                    Kind::Parked,
                    Behaviour::Still,
                    vec![Point::new(5.0, 6.0)],
                    0.0,
                )]
            },
        },
        Scenario {
            name: "goal-behind",
            what: "the goal is straight behind the robot",
            expect: Expect::Arrive,
            rows: &[
                "................",
                "................",
                "................",
                "................",
                "................",
                "................",
                "................",
                "................",
                "................",
            ],
            start: (10, 4, 0.0),
            goal: (3, 4),
            agents: none,
        },
        Scenario {
            name: "u-turn-aisle-end",
            what: "up one one-cell aisle, round the shelf end, down the next",
            expect: Expect::Arrive,
            rows: &[
                ".........",
                "@@@.@.@@@",
                "@@@.@.@@@",
                "@@@.@.@@@",
                "@@@.@.@@@",
                "@@@.@.@@@",
                "@@@.@.@@@",
                "@@@.@.@@@",
                "@@@.@.@@@",
                "@@@.@.@@@",
            ],
            start: (3, 9, -FRAC_PI_2),
            goal: (5, 9),
            agents: none,
        },
        Scenario {
            name: "person-crossing",
            what: "a person walks across the cross-aisle as the robot arrives",
            expect: Expect::Arrive,
            rows: &[
                "@@@@@@@@@..@@@@@@@@@",
                "@@@@@@@@@..@@@@@@@@@",
                "@@@@@@@@@..@@@@@@@@@",
                "@@@@@@@@@..@@@@@@@@@",
                "....................",
                "....................",
                "@@@@@@@@@..@@@@@@@@@",
                "@@@@@@@@@..@@@@@@@@@",
                "@@@@@@@@@..@@@@@@@@@",
                "@@@@@@@@@..@@@@@@@@@",
            ],
            start: (0, 4, 0.0),
            goal: (19, 5),
            agents: || {
                let mut p = Agent::new(
                    Kind::Person,
                    Behaviour::Patrol,
                    vec![Point::new(9.0, 0.0), Point::new(10.0, 9.0)],
                    0.9,
                );
                p.delay = 5.0;
                vec![p]
            },
        },
        Scenario {
            name: "walled-off-goal",
            what: "the goal is enclosed by shelves: a clear unreachable outcome",
            expect: Expect::Unreachable,
            rows: &[
                "............",
                "............",
                "......@@@@..",
                "......@..@..",
                "......@..@..",
                "......@@@@..",
                "............",
            ],
            start: (1, 1, PI),
            goal: (7, 3),
            agents: none,
        },
    ]
}
