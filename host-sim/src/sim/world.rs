//! Dynamic obstacles: people and other robots moving along aisles (scripted patrols between
//! two points, or random errands between free cells), and parked robots.
//!
//! Movers follow polylines at their own speed and yield: a mover whose next 0.6 m ahead
//! would bring it within reach of the simulated robot, or who would meet the robot within
//! the next second if both kept their velocities, waits; after waiting `patience` seconds
//! it turns back (patrols) or picks a new errand (random movers), so nobody waits for ever
//! face to face in a one-cell aisle.
//!
//! Positions are in cells; sizes, speeds and distances are metres scaled by the map's
//! cells per metre (1 on maps without a world frame, where a cell counts as a metre).

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
    /// A walking person (radius 0.25 m, up to 1.0 m/s).
    Person,
    /// Another robot (radius 0.3 m).
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

/// Errands go to any free cell on maps of up to this many cells a side; on bigger maps to a
/// free cell at most this many cells away along each axis (a person walks to a nearby aisle,
/// not across the hall), so that errand searches stay small.
pub const ERRAND_REACH: usize = 128;

/// Most open-list slots of an errand search (a search that outgrows them is a failed
/// errand; the reach keeps the frontier far below).
const ERRAND_OPEN: usize = 1 << 16;

/// The dynamic obstacles of a mission.
pub struct World {
    /// The obstacles.
    pub agents: Vec<Agent>,
    rng: Xoshiro256PlusPlus,
    /// Made when the first random mover needs it, so that a mission without random movers
    /// allocates nothing per cell.
    errands: Option<Errands>,
    path: Box<Path<4096>>,
    /// Cells per metre.
    scale: f32,
}

/// Scratch of the errand searches: A* nodes (4 bytes a cell), a bounded open list, and on
/// maps within [`ERRAND_REACH`] a side the list of free cells (4 bytes a free cell).
struct Errands {
    nodes: Vec<AStarNode>,
    open: Vec<OpenSlot>,
    /// Every free cell on small maps; empty on big ones, where cells are drawn at random.
    free: Vec<Cell>,
    small: bool,
}

impl Errands {
    fn new(grid: GridRef<'_>) -> Self {
        let small = grid.width() <= ERRAND_REACH && grid.height() <= ERRAND_REACH;
        let free = if small {
            (0..grid.cells())
                .map(|i| grid.cell(i))
                .filter(|c| grid.is_free(*c))
                .collect()
        } else {
            Vec::new()
        };
        Errands {
            nodes: vec![AStarNode::EMPTY; grid.cells()],
            open: vec![OpenSlot::EMPTY; open_capacity(grid.cells()).min(ERRAND_OPEN)],
            free,
            small,
        }
    }

    /// A random free cell: from the list on small maps (`None` when there is none; `near` is
    /// ignored), else one of 64 draws within [`ERRAND_REACH`] of `near` (anywhere without
    /// it).
    fn draw(
        &self,
        rng: &mut Xoshiro256PlusPlus,
        grid: GridRef<'_>,
        near: Option<Cell>,
    ) -> Option<Cell> {
        if self.small {
            return (!self.free.is_empty()).then(|| self.free[index(rng, self.free.len())]);
        }
        let span = |c: usize, len: usize| match near {
            Some(_) => (
                c.saturating_sub(ERRAND_REACH),
                (c + ERRAND_REACH).min(len - 1),
            ),
            None => (0, len - 1),
        };
        let at = near.unwrap_or_default();
        let (x0, x1) = span(at.x as usize, grid.width());
        let (y0, y1) = span(at.y as usize, grid.height());
        (0..64).find_map(|_| {
            let x = x0 + index(rng, x1 - x0 + 1);
            let y = y0 + index(rng, y1 - y0 + 1);
            let c = Cell::new(x as u16, y as u16);
            grid.is_free(c).then_some(c)
        })
    }
}

impl World {
    /// A world with its own random stream (its grid comes with each call), on a map of
    /// `cells_per_metre` (1 where a cell counts as a metre).
    pub fn new(seed: u64, cells_per_metre: f32) -> Self {
        World {
            agents: Vec::new(),
            rng: Xoshiro256PlusPlus::seed_from_u64(seed),
            errands: None,
            path: Box::new(Path::new()),
            scale: cells_per_metre,
        }
    }

    /// The errand scratch, made on first use.
    fn errands(&mut self, grid: GridRef<'_>) -> &mut Errands {
        self.errands.get_or_insert_with(|| Errands::new(grid))
    }

    /// A random errand route from `from`, avoiding cells within 2.5 m of `avoid` as goals.
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
        self.errands(grid);
        let self_scale = self.scale;
        let World {
            rng, errands, path, ..
        } = self;
        let Some(e) = errands.as_mut() else {
            return vec![from];
        };
        for _ in 0..20 {
            let Some(goal) = e.draw(rng, grid, Some(start)) else {
                break;
            };
            if avoid
                .iter()
                .any(|a| a.distance(goal.center()) < 2.5 * self_scale)
            {
                continue;
            }
            let out: &mut PathView = &mut **path;
            if astar::plan(grid, start, goal, &mut e.nodes, &mut e.open, out).is_ok() {
                let mut route = vec![from];
                route.extend(out.iter().skip(1));
                return route;
            }
        }
        vec![from]
    }

    /// Adds `count` random movers of `kind` at free cells away from `keep_clear` (on maps over
    /// [`ERRAND_REACH`] a side, within reach of its first point, the robot's start, so that
    /// they share its part of the hall).
    pub fn add_random(
        &mut self,
        grid: GridRef<'_>,
        kind: Kind,
        count: usize,
        keep_clear: &[Point],
    ) {
        if count == 0 {
            return;
        }
        self.errands(grid);
        let near = keep_clear.first().and_then(|p| p.cell(grid));
        for _ in 0..count {
            let mut at = None;
            for _ in 0..50 {
                let Some(e) = self.errands.as_ref() else {
                    break;
                };
                let Some(c) = e.draw(&mut self.rng, grid, near) else {
                    break;
                };
                if keep_clear
                    .iter()
                    .all(|p| p.distance(c.center()) > 3.0 * self.scale)
                {
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
            let mut a = Agent::new(kind, Behaviour::Random, route, speed * self.scale);
            a.radius *= self.scale;
            a.patience = uniform(&mut self.rng, 1.5, 4.0);
            self.agents.push(a);
        }
    }

    /// Advances every mover by `dt`; `robot` is the simulated robot (position, radius in
    /// cells) and `robot_vel` its velocity (cells/s).
    pub fn step(
        &mut self,
        grid: GridRef<'_>,
        dt: f32,
        robot: (Point, f32),
        robot_vel: (f32, f32),
        goal: Point,
    ) {
        let k = self.scale;
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
            // Yield to the robot: would the next 0.6 m bring us within reach, or would we
            // meet within the next second, both keeping our velocities?
            let ahead = Point::new(a.pos.x + ux * 0.6 * k, a.pos.y + uy * 0.6 * k);
            let reach = a.radius + robot.1 + 0.15 * k;
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
                    && (ahead.distance(robot.0) < reach
                        || a.pos.distance(robot.0) < reach + 0.3 * k)
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

#[cfg(test)]
mod tests {
    use super::*;
    use planner_core::grid::GridBuf;

    /// An open `w x h` floor with a wall across its middle row (a gap at the left end).
    fn floor(w: usize, h: usize) -> GridBuf {
        let mut g = GridBuf::new(w, h).unwrap();
        for x in 2..w {
            g.set_blocked(x, h / 2, true).unwrap();
        }
        g
    }

    #[test]
    fn no_random_movers_no_errand_scratch() {
        let g = floor(40, 30);
        let mut world = World::new(1, 1.0);
        world.add_random(g.view(), Kind::Person, 0, &[]);
        assert!(world.errands.is_none());
        world.add_random(g.view(), Kind::Person, 2, &[]);
        let e = world.errands.as_ref().unwrap();
        assert!(e.small && e.nodes.len() == 1200 && e.free.len() == 1200 - 38);
        assert_eq!(world.agents.len(), 2);
    }

    #[test]
    fn movers_on_big_maps_start_near_the_robot_and_run_errands_within_reach() {
        let g = floor(1000, 600);
        let v = g.view();
        let robot = Point::new(700.0, 100.0);
        let mut world = World::new(7, 1.0);
        world.add_random(v, Kind::Robot, 6, &[robot]);
        let e = world.errands.as_ref().unwrap();
        assert!(!e.small && e.free.is_empty() && e.open.len() == ERRAND_OPEN);
        assert_eq!(world.agents.len(), 6);
        let mut moving = 0;
        for a in &world.agents {
            assert!(a.route.iter().all(|p| v.is_free(p.cell(v).unwrap())));
            let (from, to) = (a.route[0], *a.route.last().unwrap());
            let reach = ERRAND_REACH as f32;
            assert!((from.x - to.x).abs() <= reach && (from.y - to.y).abs() <= reach);
            assert!((from.x - robot.x).abs() <= reach && (from.y - robot.y).abs() <= reach);
            assert!(from.distance(robot) > 3.0);
            moving += usize::from(a.route.len() > 1);
        }
        assert!(moving >= 4, "{moving} of 6 movers got an errand");
    }
}
