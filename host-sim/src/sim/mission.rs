//! One mission: plan globally, drive with DWA among dynamic obstacles, replan when the path
//! is blocked or the robot is stuck, and measure everything the report needs.

use super::kinematics::DiffDrive;
use super::pathfit::{self, FitParams};
use super::planner::{GlobalPlanRequest, GlobalPlanner, PlanFailure, PlannedPath};
use super::world::{Agent, Kind, World};
use planner_core::dwa::{Dwa, DwaConfig, DwaState, Event};
use planner_core::geometry::{Cell, Point, distance_to_polyline, point_clearance};
use planner_core::grid::GridBuf;
use planner_core::planner::{Blend, PlanParams, PlannerKind};

/// Everything that defines a mission.
#[derive(Clone)]
pub struct MissionSpec {
    /// Name for tables and titles.
    pub name: String,
    /// The static map: what the robot collides with.
    pub grid: GridBuf,
    /// What the global planner plans on, when not `grid`: the map inflated by the robot's
    /// radius (same size).
    pub plan_grid: Option<GridBuf>,
    /// Metres per cell: the report's lengths are metres (1 on maps without a world frame,
    /// where a cell counts as a metre); the movers' sizes and speeds scale with it.
    pub metres_per_cell: f32,
    /// Start pose (`v = w = 0` normally).
    pub start: DwaState,
    /// Goal cell.
    pub goal: Cell,
    /// Global planner.
    pub algo: PlannerKind,
    /// Its parameters.
    pub params: PlanParams,
    /// Seed of the planner and of the random movers.
    pub seed: u64,
    /// Scripted obstacles.
    pub agents: Vec<Agent>,
    /// Random people to add.
    pub people: usize,
    /// Random robots to add.
    pub robots: usize,
    /// Local planner.
    pub dwa: DwaConfig,
    /// Robot kinematics.
    pub drive: DiffDrive,
    /// Give up after this many simulated seconds (`None`: 40 s + 4 x planned length / v_max).
    pub time_limit: Option<f32>,
    /// Keep the trajectory, trails and paths (pictures); off in soaks.
    pub record: bool,
}

/// How a mission ended.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Outcome {
    /// Within the goal tolerance.
    Arrived,
    /// The goal is walled off (the planner proves it).
    Unreachable,
    /// The time limit ran out.
    Timeout,
    /// The planner failed otherwise.
    PlanFailed(String),
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Outcome::Arrived => f.write_str("Arrived"),
            Outcome::Unreachable => f.write_str("Unreachable"),
            Outcome::Timeout => f.write_str("Timeout"),
            Outcome::PlanFailed(why) => write!(f, "PlanFailed ({why})"),
        }
    }
}

/// One global plan of a mission.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PlanRecord {
    /// `initial`, `blocked` or `stuck`.
    pub reason: &'static str,
    /// Simulated time of the request (s).
    pub at: f32,
    /// Length (m).
    pub length: f32,
    /// Evaluations (or expansions).
    pub evaluations: u64,
    /// Wall-clock planning time (ms).
    pub time_ms: f64,
    /// The waypoints (cells).
    #[serde(skip)]
    pub points: Vec<Point>,
    /// Best cost per iteration.
    #[serde(skip)]
    pub history: Vec<f32>,
}

/// Figures of a mission (the JSON report).
#[derive(Clone, Debug, serde::Serialize)]
pub struct MissionResult {
    /// Mission name.
    pub name: String,
    /// Outcome.
    pub outcome: Outcome,
    /// Arrived with no collision.
    pub success: bool,
    /// Contacts with static obstacles (episodes).
    pub collisions_static: u32,
    /// Contacts with dynamic obstacles (episodes).
    pub collisions_dynamic: u32,
    /// Of those, episodes during which the robot moved (faster than 5 cm/s at some step): a
    /// person walking into a standing robot is not one.
    pub contacts_moving: u32,
    /// Simulated time to the goal (s).
    pub time_to_goal: Option<f32>,
    /// Simulated time (s).
    pub sim_time: f32,
    /// Driven length (m).
    pub driven_length: f32,
    /// Length of the first global path (m).
    pub planned_length: f32,
    /// Driven / planned.
    pub length_ratio: f32,
    /// RMS distance to the current global path (m).
    pub rms_cross_track: f32,
    /// Largest distance to the current global path (m).
    pub max_cross_track: f32,
    /// Smallest clearance between the footprint and a static obstacle (m).
    pub min_clearance_static: f32,
    /// The same at the start pose (m): where the start is closer than the margin, the robot
    /// keeps what it has there.
    pub start_clearance_static: f32,
    /// Smallest clearance between the footprint and a dynamic obstacle (m).
    pub min_clearance_dynamic: Option<f32>,
    /// Replans after the first plan.
    pub replans: u32,
    /// Progress-checker events.
    pub stuck_events: u32,
    /// Oscillation events.
    pub oscillation_events: u32,
    /// The plans.
    pub plans: Vec<PlanRecord>,
    /// Driven trajectory (cells).
    #[serde(skip)]
    pub trajectory: Vec<Point>,
    /// Final state of the obstacles (with trails when recorded).
    #[serde(skip)]
    pub agents: Vec<Agent>,
}

fn record(reason: &'static str, at: f32, p: &PlannedPath, keep: bool, mpc: f32) -> PlanRecord {
    PlanRecord {
        reason,
        at,
        length: p.length * mpc,
        evaluations: p.evaluations,
        time_ms: p.time.as_secs_f64() * 1e3,
        points: if keep || reason == "initial" {
            p.points.clone()
        } else {
            Vec::new()
        },
        history: if reason == "initial" {
            p.history.clone()
        } else {
            Vec::new()
        },
    }
}

/// Distance from point `p` to the closed unit square of cell `c`.
fn square_distance(p: Point, c: (isize, isize)) -> f32 {
    let gx = ((p.x - c.0 as f32).abs() - 0.5).max(0.0);
    let gy = ((p.y - c.1 as f32).abs() - 0.5).max(0.0);
    (gx * gx + gy * gy).sqrt()
}

/// Whether a standing obstacle sits on the path within `ahead` cells of the robot, closer
/// to it than the two radii and `slack`.
fn path_blocked(
    path: &[Point],
    robot: Point,
    agents: &[Agent],
    (radius, slack): (f32, f32),
    ahead: f32,
) -> bool {
    // Follow the path from the segment nearest the robot.
    let mut best = (f32::INFINITY, 0usize);
    for (i, s) in path.windows(2).enumerate() {
        let d = distance_to_polyline(robot, s);
        if d < best.0 {
            best = (d, i);
        }
    }
    let mut left = ahead;
    let mut pieces: Vec<Point> = vec![robot];
    for p in path.iter().skip(best.1 + 1) {
        let last = *pieces.last().unwrap_or(&robot);
        let d = last.distance(*p);
        pieces.push(*p);
        left -= d;
        if left <= 0.0 {
            break;
        }
    }
    agents.iter().any(|a| {
        !a.moving()
            && a.pos.distance(robot) > 1e-3
            && distance_to_polyline(a.pos, &pieces) < a.radius + radius + slack
    })
}

/// Runs a mission with `planner`.
pub fn run(spec: &MissionSpec, planner: &mut dyn GlobalPlanner) -> MissionResult {
    run_with_progress(spec, planner, &mut |_, _| {})
}

/// [`run`], calling `tick(simulated time, time limit)` every second of simulated time.
pub fn run_with_progress(
    spec: &MissionSpec,
    planner: &mut dyn GlobalPlanner,
    tick: &mut dyn FnMut(f32, f32),
) -> MissionResult {
    let grid = spec.grid.view();
    let plan_grid = spec.plan_grid.as_ref().map_or(grid, GridBuf::view);
    // Cells per metre, for the distances below that are metres on 1 m cells.
    let (mpc, k) = (spec.metres_per_cell, 1.0 / spec.metres_per_cell);
    let fit = FitParams {
        spacing: 0.25 * k,
        target: 1.0 * k,
        ..FitParams::default()
    };
    let goal_pt = spec.goal.center();
    let mut result = MissionResult {
        name: spec.name.clone(),
        outcome: Outcome::Timeout,
        success: false,
        collisions_static: 0,
        collisions_dynamic: 0,
        contacts_moving: 0,
        time_to_goal: None,
        sim_time: 0.0,
        driven_length: 0.0,
        planned_length: f32::NAN,
        length_ratio: f32::NAN,
        rms_cross_track: 0.0,
        max_cross_track: 0.0,
        min_clearance_static: f32::INFINITY,
        start_clearance_static: mpc
            * (point_clearance(grid, spec.start.position(), spec.dwa.radius + 5.0 * k)
                - spec.dwa.radius),
        min_clearance_dynamic: None,
        replans: 0,
        stuck_events: 0,
        oscillation_events: 0,
        plans: Vec::new(),
        trajectory: Vec::new(),
        agents: Vec::new(),
    };
    let request = |start: Cell, seed: u64, params: PlanParams| GlobalPlanRequest {
        start,
        goal: spec.goal,
        algo: spec.algo,
        params,
        seed,
    };
    // With a safety margin the first plan keeps the footprint and margin off the shelves by
    // itself (the blended objective). Replans around standing obstacles stay by length: the
    // blended path turns square at aisle mouths, which DWA with a margin could not enter
    // (scenario parked-robot-replan).
    // Clearance on the planning map: on a map inflated by the radius, beyond the footprint.
    let footprint = if spec.plan_grid.is_some() {
        0.0
    } else {
        spec.dwa.radius
    };
    let first_params = if spec.dwa.margin > 0.0 && spec.params.blend.is_length() {
        PlanParams {
            blend: Blend {
                clearance: footprint + spec.dwa.margin + 0.05 * k,
                clearance_weight: 16.0,
                turn_weight: 1.0,
            },
            ..spec.params
        }
    } else {
        spec.params
    };
    let start_cell = spec.start.position().cell(grid).unwrap_or_default();
    // On a map inflated by the radius, the route is planned on it inflated by the margin as
    // well, so that it takes only passages DWA drives with its margin (one narrower left the
    // robot stuck on the AWS map); on the radius alone where that closes an end or the way.
    let with_margin = match &spec.plan_grid {
        Some(_) if spec.dwa.margin > 0.0 => {
            spec.grid.inflated(spec.dwa.radius + spec.dwa.margin).ok()
        }
        _ => None,
    }
    .filter(|g| {
        [start_cell, spec.goal]
            .iter()
            .all(|c| !g.view().is_blocked(c.x as isize, c.y as isize))
    });
    let mut route_grid = plan_grid;
    let mut first = Err(PlanFailure::Unreachable);
    for candidate in with_margin
        .as_ref()
        .map(GridBuf::view)
        .into_iter()
        .chain([plan_grid])
    {
        route_grid = candidate;
        first = planner
            .set_map(route_grid)
            .and_then(|()| planner.plan(&request(start_cell, spec.seed, first_params)));
        if first.is_ok() {
            break;
        }
    }
    let mut path = match first {
        Ok(mut p) => {
            p.points = pathfit::fit(route_grid, &p.points, &fit);
            p
        }
        Err(PlanFailure::Unreachable) => {
            result.outcome = Outcome::Unreachable;
            return result;
        }
        Err(e) => {
            result.outcome = Outcome::PlanFailed(e.to_string());
            return result;
        }
    };
    result.planned_length = path.length;
    result
        .plans
        .push(record("initial", 0.0, &path, spec.record, mpc));
    let Ok(mut dwa) = Dwa::new(spec.dwa) else {
        result.outcome = Outcome::PlanFailed("invalid DWA configuration".into());
        return result;
    };
    let mut world = World::new(spec.seed ^ 0x5151_0000, k);
    world.agents = spec.agents.clone();
    let keep_clear = [spec.start.position(), goal_pt];
    world.add_random(grid, Kind::Person, spec.people, &keep_clear);
    world.add_random(grid, Kind::Robot, spec.robots, &keep_clear);

    let dt = spec.dwa.dt;
    let radius = spec.dwa.radius;
    let limit = spec
        .time_limit
        .unwrap_or(40.0 + 4.0 * path.length / spec.dwa.v_max);
    let mut state = spec.start;
    let mut t = 0.0f32;
    let mut blocked_for = 0.0f32;
    let mut last_replan = -10.0f32;
    let mut on_temp_map = false;
    let mut in_static = false;
    let mut in_dynamic = false;
    let mut moved_in_contact = false;
    let mut sq_sum = 0.0f64;
    let mut samples = 0u64;
    let mut replan_seed = spec.seed;
    result.trajectory.push(state.position());
    let mut steps = 0u32;
    while t < limit {
        steps += 1;
        if steps.is_multiple_of(10) {
            tick(t, limit);
        }
        let discs = world.discs();
        let cmd = match dwa.step(&state, grid, &discs, &path.points) {
            Ok(c) => c,
            Err(e) => {
                result.outcome = Outcome::PlanFailed(format!("DWA: {e}"));
                break;
            }
        };
        if cmd.mode == planner_core::dwa::Mode::Arrived {
            result.outcome = Outcome::Arrived;
            result.time_to_goal = Some(t);
            break;
        }
        let mut reason = None;
        if cmd.event == Event::Stuck {
            reason = Some("stuck");
        }
        if path_blocked(
            &path.points,
            state.position(),
            &world.agents,
            (radius, 0.05 * k),
            4.0 * k,
        ) {
            blocked_for += dt;
        } else {
            blocked_for = 0.0;
        }
        if blocked_for > 1.0 {
            reason = Some("blocked");
        }
        if let Some(reason) = reason.filter(|_| t - last_replan > 2.0) {
            last_replan = t;
            // Mark the cells under nearby standing obstacles (and anything touching the
            // robot's way when stuck) as blocked on a copy of the planning map.
            let robot_cell = state.position().cell(grid);
            let mut tmp = GridBuf::from_view(route_grid);
            for a in &world.agents {
                let near = a.pos.distance(state.position()) < 8.0 * k;
                if !near || (a.moving() && reason == "blocked") {
                    continue;
                }
                let reach = a.radius + radius;
                let span = reach.ceil() as isize + 1;
                let (cx, cy) = (a.pos.x.round() as isize, a.pos.y.round() as isize);
                for y in cy - span..=cy + span {
                    for x in cx - span..=cx + span {
                        let c = (x, y);
                        if !grid.contains(x, y) || square_distance(a.pos, c) >= reach - 0.2 * k {
                            continue;
                        }
                        let cell = Cell::new(x as u16, y as u16);
                        if Some(cell) == robot_cell || cell == spec.goal {
                            continue;
                        }
                        let _ = tmp.set_blocked(x as usize, y as usize, true);
                    }
                }
            }
            if let Some(from) = robot_cell {
                replan_seed = replan_seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
                let planned = planner
                    .set_map(tmp.view())
                    .and_then(|()| planner.plan(&request(from, replan_seed, spec.params)));
                on_temp_map = true;
                if let Ok(mut p) = planned {
                    // Start the new path at the robot, not at its cell centre, and keep it
                    // off the walls and off the standing obstacles marked on `tmp`.
                    if let Some(first) = p.points.first_mut() {
                        *first = state.position();
                    }
                    p.points = pathfit::fit(tmp.view(), &p.points, &fit);
                    path = p;
                    result.replans += 1;
                    result
                        .plans
                        .push(record(reason, t, &path, spec.record, mpc));
                    dwa.reset_path();
                    blocked_for = 0.0;
                }
            }
        }
        if on_temp_map && t - last_replan > 5.0 {
            let _ = planner.set_map(route_grid);
            on_temp_map = false;
        }
        let before = state.position();
        spec.drive.step(&mut state, cmd.v, cmd.w, dt);
        let robot_vel = (state.v * state.theta.cos(), state.v * state.theta.sin());
        world.step(grid, dt, (state.position(), radius), robot_vel, goal_pt);
        t += dt;
        let pos = state.position();
        result.driven_length += before.distance(pos);
        let cross = distance_to_polyline(pos, &path.points);
        sq_sum += (cross as f64).powi(2);
        samples += 1;
        result.max_cross_track = result.max_cross_track.max(cross);
        let cs = point_clearance(grid, pos, radius + 5.0 * k) - radius;
        result.min_clearance_static = result.min_clearance_static.min(cs);
        if cs < -1e-4 {
            if !in_static {
                result.collisions_static += 1;
            }
            in_static = true;
        } else {
            in_static = false;
        }
        let cd = world
            .agents
            .iter()
            .map(|a| a.pos.distance(pos) - a.radius - radius)
            .fold(f32::INFINITY, f32::min);
        if cd.is_finite() {
            let m = result.min_clearance_dynamic.unwrap_or(f32::INFINITY);
            result.min_clearance_dynamic = Some(m.min(cd));
        }
        if cd < -1e-4 {
            if !in_dynamic {
                result.collisions_dynamic += 1;
                moved_in_contact = false;
            }
            in_dynamic = true;
            if state.v.abs() > 0.05 * k && !moved_in_contact {
                moved_in_contact = true;
                result.contacts_moving += 1;
            }
        } else {
            in_dynamic = false;
        }
        if spec.record {
            result.trajectory.push(pos);
        }
    }
    result.sim_time = t;
    if !spec.record {
        result.trajectory.push(state.position());
        for a in &mut world.agents {
            a.trail.clear();
        }
    }
    result.stuck_events = dwa.stuck_events();
    result.oscillation_events = dwa.oscillation_events();
    result.rms_cross_track = if samples > 0 {
        (sq_sum / samples as f64).sqrt() as f32
    } else {
        0.0
    };
    result.length_ratio = result.driven_length / result.planned_length;
    // The report in metres (the ratio is the same in either unit).
    for v in [
        &mut result.driven_length,
        &mut result.planned_length,
        &mut result.rms_cross_track,
        &mut result.max_cross_track,
        &mut result.min_clearance_static,
    ] {
        *v *= mpc;
    }
    result.min_clearance_dynamic = result.min_clearance_dynamic.map(|c| c * mpc);
    result.success = result.outcome == Outcome::Arrived
        && result.collisions_static == 0
        && result.collisions_dynamic == 0;
    result.agents = world.agents;
    result
}
