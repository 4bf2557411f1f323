//! Dynamic obstacles: people and other robots moving along aisles (scripted patrols between
//! two points, or random errands between free cells), and parked robots.
//!
//! Movers follow polylines at their own speed and yield: a mover whose next 0.6 cells
//! ahead would bring it within reach of the simulated robot, or who would meet the robot
//! within the next second if both kept their velocities, waits; after waiting
//! `patience` seconds it turns back (patrols) or picks a new errand (random movers), so
//! nobody waits for ever face to face in a one-cell aisle.

use planner_core::dwa::DynamicDisc;
use planner_core::geometry::{Cell, Point};
use planner_core::grid::GridRef;
use planner_core::path::{Path, PathView};
use planner_core::search::astar::{self, AStarNode, OpenSlot, open_capacity};
use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Uniform index below `n` (n > 0).
fn index(rng: &mut Xoshiro256PlusPlus, n: usize) -> usize {
    (rng.next_u64() % n as u64) as usize
}

/// Uniform value in `lo..hi`.
fn uniform(rng: &mut Xoshiro256PlusPlus, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32
}

/// What an obstacle is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Kind {
    /// A walking person (radius 0.25, up to 1.0 cell/s).
    Person,
    /// Another robot (radius 0.3).
    Robot,
    /// A robot or pallet that does not move.
    Parked,
}

/// How an obstacle moves.
#[derive(Clone, Debug)]
pub enum Behaviour {
    /// Back and forth along the route.
    Patrol,
    /// A new random errand after each arrival.
    Random,
    /// Never moves.
    Still,
}

/// One dynamic obstacle.
#[derive(Clone, Debug)]
pub struct Agent {
    /// Kind.
    pub kind: Kind,
    /// Movement.
    pub behaviour: Behaviour,
    /// Position.
    pub pos: Point,
    /// Current velocity.
    pub vel: (f32, f32),
    /// Radius (cells).
    pub radius: f32,
    /// Walking speed (cells/s).
    pub speed: f32,
    /// Route being followed.
    pub route: Vec<Point>,
    /// Next route index.
    pub next: usize,
    /// Seconds waited so far.
    pub waited: f32,
    /// Seconds to wait before turning back.
    pub patience: f32,
    /// Seconds before starting to move.
    pub delay: f32,
    /// Positions over time (for pictures).
    pub trail: Vec<Point>,
}

impl Agent {
    /// A mover along `route` (patrol) or a parked obstacle (`route` of one point).
    pub fn new(kind: Kind, behaviour: Behaviour, route: Vec<Point>, speed: f32) -> Self {
        let pos = route.first().copied().unwrap_or_default();
        Agent {
            kind,
            behaviour,
            pos,
            vel: (0.0, 0.0),
            radius: match kind {
                Kind::Person => 0.25,
                Kind::Robot | Kind::Parked => 0.3,
            },
            speed,
            next: 1.min(route.len().saturating_sub(1)),
            route,
            waited: 0.0,
            patience: 3.0,
            delay: 0.0,
            trail: vec![pos],
        }
    }

    /// The disc the local planner sees.
    pub fn disc(&self) -> DynamicDisc {
        DynamicDisc {
            x: self.pos.x,
            y: self.pos.y,
            r: self.radius,
            vx: self.vel.0,
            vy: self.vel.1,
        }
    }

    /// Speed now.
    pub fn moving(&self) -> bool {
        self.vel.0.abs() + self.vel.1.abs() > 0.02
    }
}

/// The dynamic obstacles of a mission.
pub struct World {
    /// The obstacles.
    pub agents: Vec<Agent>,
    rng: Xoshiro256PlusPlus,
    nodes: Vec<AStarNode>,
    open: Vec<OpenSlot>,
    path: Box<Path<4096>>,
    free: Vec<Cell>,
}

impl World {
    /// A world on `grid` with its own random stream.
    pub fn new(grid: GridRef<'_>, seed: u64) -> Self {
        let free = (0..grid.cells())
            .map(|i| grid.cell(i))
            .filter(|c| grid.is_free(*c))
            .collect();
        World {
            agents: Vec::new(),
            rng: Xoshiro256PlusPlus::seed_from_u64(seed),
            nodes: vec![AStarNode::EMPTY; grid.cells()],
            open: vec![OpenSlot::EMPTY; open_capacity(grid.cells())],
            path: Box::new(Path::new()),
            free,
        }
    }

    /// A random errand route from `from`, avoiding cells within 2 of `avoid` as goals.
    /// Gives agent `i` a new errand from where it stands.
    fn send_on_errand(&mut self, i: usize, grid: GridRef<'_>, avoid: &[Point]) {
        let from = self.agents[i].pos;
        let route = self.errand(grid, from, avoid);
        let a = &mut self.agents[i];
        a.route = route;
        a.next = 1.min(a.route.len() - 1);
    }

    fn errand(&mut self, grid: GridRef<'_>, from: Point, avoid: &[Point]) -> Vec<Point> {
        let Some(start) = from.cell(grid) else {
            return vec![from];
        };
        for _ in 0..20 {
            if self.free.is_empty() {
                break;
            }
            let goal = self.free[index(&mut self.rng, self.free.len())];
            if avoid.iter().any(|a| a.distance(goal.center()) < 2.5) {
                continue;
            }
            let out: &mut PathView = &mut *self.path;
            if astar::plan(grid, start, goal, &mut self.nodes, &mut self.open, out).is_ok() {
                let mut route = vec![from];
                route.extend(out.iter().skip(1));
                return route;
            }
        }
        vec![from]
    }

    /// Adds `count` random movers of `kind` at free cells away from `keep_clear`.
    pub fn add_random(
        &mut self,
        grid: GridRef<'_>,
        kind: Kind,
        count: usize,
        keep_clear: &[Point],
    ) {
        for _ in 0..count {
            let mut at = None;
            for _ in 0..50 {
                if self.free.is_empty() {
                    break;
                }
                let c = self.free[index(&mut self.rng, self.free.len())];
                if keep_clear.iter().all(|p| p.distance(c.center()) > 3.0) {
                    at = Some(c.center());
                    break;
                }
            }
            let Some(at) = at else { continue };
            let route = self.errand(grid, at, keep_clear);
            let speed = match kind {
                Kind::Person => uniform(&mut self.rng, 0.5, 1.0),
                _ => uniform(&mut self.rng, 0.4, 0.8),
            };
            let mut a = Agent::new(kind, Behaviour::Random, route, speed);
            a.patience = uniform(&mut self.rng, 1.5, 4.0);
            self.agents.push(a);
        }
    }

    /// Advances every mover by `dt`; `robot` is the simulated robot (position, radius) and
    /// `robot_vel` its velocity (cells/s).
    pub fn step(
        &mut self,
        grid: GridRef<'_>,
        dt: f32,
        robot: (Point, f32),
        robot_vel: (f32, f32),
        goal: Point,
    ) {
        for i in 0..self.agents.len() {
            let a = &mut self.agents[i];
            a.vel = (0.0, 0.0);
            if matches!(a.behaviour, Behaviour::Still) || a.route.len() < 2 {
                if matches!(a.behaviour, Behaviour::Random) {
                    self.send_on_errand(i, grid, &[robot.0, goal]);
                }
                continue;
            }
            if a.delay > 0.0 {
                a.delay -= dt;
                continue;
            }
            let target = a.route[a.next];
            let (dx, dy) = (target.x - a.pos.x, target.y - a.pos.y);
            let d = (dx * dx + dy * dy).sqrt();
            let step = a.speed * dt;
            let (ux, uy) = if d > 1e-6 {
                (dx / d, dy / d)
            } else {
                (0.0, 0.0)
            };
            // Yield to the robot: would the next 0.6 cells bring us within reach, or would
            // we meet within the next second, both keeping our velocities?
            let ahead = Point::new(a.pos.x + ux * 0.6, a.pos.y + uy * 0.6);
            let reach = a.radius + robot.1 + 0.15;
            let closing = (robot.0.x - a.pos.x) * ux + (robot.0.y - a.pos.y) * uy > 0.0;
            let meet = (1..=10).any(|k| {
                let t = k as f32 * 0.1;
                let me = Point::new(a.pos.x + ux * a.speed * t, a.pos.y + uy * a.speed * t);
                let it = Point::new(robot.0.x + robot_vel.0 * t, robot.0.y + robot_vel.1 * t);
                let now = a.pos.distance(robot.0);
                // Only if walking on makes it worse than standing would.
                let still = a.pos.distance(it);
                me.distance(it) < reach && me.distance(it) < still.min(now)
            });
            if meet
                || closing
                    && (ahead.distance(robot.0) < reach || a.pos.distance(robot.0) < reach + 0.3)
            {
                a.waited += dt;
                if a.waited > a.patience {
                    a.waited = 0.0;
                    match a.behaviour {
                        Behaviour::Patrol => {
                            // Turn back: reverse the remaining route.
                            let mut back: Vec<Point> = a.route[..a.next].to_vec();
                            back.push(a.pos);
                            back.reverse();
                            a.route = back;
                            a.next = 1.min(a.route.len() - 1);
                        }
                        Behaviour::Random => {
                            self.send_on_errand(i, grid, &[robot.0, goal]);
                        }
                        Behaviour::Still => {}
                    }
                }
                continue;
            }
            a.waited = 0.0;
            if d <= step {
                a.pos = target;
                if a.next + 1 < a.route.len() {
                    a.next += 1;
                } else {
                    match a.behaviour {
                        Behaviour::Patrol => {
                            a.route.reverse();
                            a.next = 1.min(a.route.len() - 1);
                        }
                        Behaviour::Random => {
                            self.send_on_errand(i, grid, &[robot.0, goal]);
                        }
                        Behaviour::Still => {}
                    }
                }
            } else {
                a.pos = Point::new(a.pos.x + ux * step, a.pos.y + uy * step);
            }
            let a = &mut self.agents[i];
            a.vel = (ux * a.speed, uy * a.speed);
            a.trail.push(a.pos);
        }
    }

    /// The discs the local planner sees.
    pub fn discs(&self) -> Vec<DynamicDisc> {
        self.agents.iter().map(Agent::disc).collect()
    }
}
