//! The firmware scenario, shared verbatim by the MCU image (`main.rs`) and the host test
//! (`tests/tests/firmware_digest.rs` includes this file with `#[path]`), so both compute the
//! same plans and the same digest.
//!
//! Plans: the exact any-angle planner, TCLHHO and IGWO (population 30, 500 iterations,
//! corridor encoding on the any-angle guide, seed [`SEED`]) on `Lei2024Warehouse`'s 40x40 warehouse
//! and on a 64x64 warehouse: the map in a [`Site`], everything a plan needs in one
//! [`Storage`] (planner-core's `PlanStorage`: the map's mesh, built by [`prepare`], a query's
//! scratch, the guide, stations, the optimizer and the path), both `static`s on the MCU,
//! with capacity 64x64 cells, population 30, dimension 64. The DWA loop follows an A* route,
//! with [`Nodes`] in the memory the plan storage used (the MCU shares it; the phases never
//! overlap).
//!
//! Digest: FNV-1a (64 bit) over the little-endian bytes of, per case: the case index, the
//! status (0 = ok, else 1 + the `PlanError` code), the path length, initial and final cost
//! (`f32::to_bits`), turns, evaluations, iterations, best iteration, the waypoint count and
//! every waypoint's `x` and `y` bits. Only integers are printed (no float formatting).

use planner_core::dwa::{Dwa, DwaConfig, DwaState, DynamicDisc, Mode};
use planner_core::geometry::{Cell, point_clearance};
use planner_core::grid::{Grid, words_for};
use planner_core::maps::{MapKind, lei2024_warehouse};
use planner_core::path::{self, Path};
use planner_core::planner::{AlgorithmKind, PlanOptions, PlanParams, PlanStorage};
use planner_core::search::astar::{self, AStarNode, OpenSlot};
use planner_core::{PlanError, Point};

/// Map capacity: side length.
pub const SIDE: usize = 64;
/// Map capacity: cells.
pub const CELLS: usize = SIDE * SIDE;
/// Grid words for the capacity.
pub const WORDS: usize = words_for(SIDE, SIDE);
/// Population capacity.
pub const POP: usize = 30;
/// Dimension capacity.
pub const DIM: usize = 64;
/// Waypoint capacity of the guide route and of the result.
pub const PATH_CAP: usize = 256;
/// A* open-list slots. The largest open list of A* on these maps is 68 (40x40) and 110
/// (64x64) from the start to any free cell (`cargo run -p planner-core --example open_peak`;
/// 1920 on Moving AI's 340x164 warehouse, 123 on its 32x32 random map): 512 leaves room for
/// other 64x64 maps, and a search that outgrows it fails with `CapacityExceeded`.
pub const OPEN: usize = 512;
/// Waypoint capacity of the DWA loop's route (the first [`DWA_ROUTE`] cells of a plan: at
/// most one point per cell plus the cut point).
pub const DWA_ROUTE_CAP: usize = 16;
/// The seed of every stochastic plan.
pub const SEED: u64 = 0x5EED_0008;

/// Rectangles of the any-angle mesh: the 40x40 warehouse needs 56, the 64x64 one 137.
pub const RECTS: usize = 144;
/// Links of the mesh (100 and 256).
pub const LINKS: usize = 272;
/// Any-angle open-list nodes. With 300, the plans from the start to every free cell of both
/// maps are proven shortest (at most 1178 nodes are pushed at once without dropping; a full
/// list drops the least promising ones, and a plan reports whether that could have
/// mattered).
pub const SEARCH_OPEN: usize = 300;

/// Everything a plan of the scenario needs: the loaded map's mesh and a query's scratch, the
/// guide route, stations, TCLHHO or IGWO state and the path. All-zero bytes, so a `static`
/// of it is in `.bss`.
pub type Storage = PlanStorage<POP, DIM, PATH_CAP, RECTS, LINKS, SEARCH_OPEN>;

/// The loaded map, its start and goal.
pub struct Site {
    /// The current map (`None` until [`load`]: a `Some` placeholder would be the only
    /// non-zero bytes of the firmware's `static`, which would then be copied from flash
    /// instead of zeroed in `.bss`).
    pub grid: Option<Grid<WORDS>>,
    /// Start.
    pub start: Cell,
    /// Goal.
    pub goal: Cell,
}

impl Site {
    /// No map yet, all zero bytes.
    pub const fn new() -> Self {
        Site {
            grid: None,
            start: Cell::new(0, 0),
            goal: Cell::new(0, 0),
        }
    }
}

impl Default for Site {
    fn default() -> Self {
        Self::new()
    }
}

/// A* search state for the DWA loop's route: a node per cell of the capacity (4 bytes),
/// [`OPEN`] open-list slots (12 bytes) and the route. All-zero bytes, so a `static` of it is
/// in `.bss`.
pub struct Nodes {
    /// One per cell.
    pub nodes: [AStarNode; CELLS],
    /// The open list.
    pub open: [OpenSlot; OPEN],
    /// The A* route.
    pub route: Path<PATH_CAP>,
}

impl Nodes {
    /// Fresh search state.
    pub const fn new() -> Self {
        Nodes {
            nodes: [AStarNode::EMPTY; CELLS],
            open: [OpenSlot::EMPTY; OPEN],
            route: Path::new(),
        }
    }
}

impl Default for Nodes {
    fn default() -> Self {
        Self::new()
    }
}

/// The planners of the scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Planner {
    /// The exact any-angle planner (the reference).
    AnyAngle,
    /// A swarm optimizer over the corridor encoding.
    Swarm(AlgorithmKind),
}

/// One plan of the scenario.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// Short name (printed).
    pub name: &'static str,
    /// Warehouse side length (`maps::lei2024_warehouse`).
    pub side: usize,
    /// The planner.
    pub planner: Planner,
}

/// The plans, in order.
pub const CASES: [Case; 6] = [
    Case {
        name: "anyangle-40",
        side: 40,
        planner: Planner::AnyAngle,
    },
    Case {
        name: "tclhho-40",
        side: 40,
        planner: Planner::Swarm(AlgorithmKind::Tclhho),
    },
    Case {
        name: "igwo-40",
        side: 40,
        planner: Planner::Swarm(AlgorithmKind::Igwo),
    },
    Case {
        name: "anyangle-64",
        side: 64,
        planner: Planner::AnyAngle,
    },
    Case {
        name: "tclhho-64",
        side: 64,
        planner: Planner::Swarm(AlgorithmKind::Tclhho),
    },
    Case {
        name: "igwo-64",
        side: 64,
        planner: Planner::Swarm(AlgorithmKind::Igwo),
    },
];

/// The integer figures of one plan.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outcome {
    /// 0 when the plan succeeded, else 1 + the `PlanError` code.
    pub status: u32,
    /// Path length in thousandths of a cell (rounded down).
    pub length_milli: u32,
    /// Path length, `f32` bits.
    pub length_bits: u32,
    /// Objective evaluations (any-angle: search nodes pushed).
    pub evaluations: u64,
    /// Optimizer iterations (any-angle: search nodes expanded).
    pub iterations: u32,
    /// Waypoints of the result.
    pub waypoints: u32,
    /// Whether the returned path passed `path::validate` (1) or not (0).
    pub valid: u32,
    /// The digest of this case alone.
    pub digest: u64,
}

/// FNV-1a, 64 bit.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(pub u64);

impl Fnv {
    /// The FNV offset basis.
    pub const fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    /// Mixes the little-endian bytes of `v`.
    pub fn u32(&mut self, v: u32) {
        for b in v.to_le_bytes() {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// Mixes a `u64` as two words, low first.
    pub fn u64(&mut self, v: u64) {
        self.u32(v as u32);
        self.u32((v >> 32) as u32);
    }
}

impl Default for Fnv {
    fn default() -> Self {
        Self::new()
    }
}

/// Loads the `side x side` warehouse of `Lei2024Warehouse` into `s` (not timed: the map would come from
/// flash or a radio on a robot).
///
/// Out of line, like [`run_case`] and [`dwa_control_loop`]: the map generator takes about
/// 5 KiB of stack, which inlined into `main` stayed reserved through every plan (peak stack
/// 8.4 KiB instead of 6.0 KiB).
#[inline(never)]
pub fn load(s: &mut Site, side: usize) -> Result<(), PlanError> {
    let map = lei2024_warehouse::<WORDS>(MapKind::Warehouse, side)
        .map_err(|_| PlanError::CapacityExceeded)?;
    s.grid = Some(map.grid);
    s.start = map.start;
    s.goal = map.goal;
    Ok(())
}

/// Builds the loaded map's any-angle mesh (once per map, timed on its own); the outcome's
/// `iterations` and `waypoints` are the rectangles and links.
#[inline(never)]
pub fn prepare(s: &Site, storage: &mut Storage) -> Outcome {
    let mut o = Outcome::default();
    let mut h = Fnv::new();
    h.u32(0x3E5);
    match s.grid.as_ref().map(|g| storage.prepare(g.view())) {
        Some(Ok(())) => {
            let mesh = storage.mesh();
            o.iterations = mesh.rects() as u32;
            o.waypoints = mesh.links() as u32;
            o.valid = 1;
            h.u32(o.iterations);
            h.u32(o.waypoints);
        }
        Some(Err(e)) => o.status = error_code(e),
        None => o.status = u32::MAX,
    }
    h.u32(o.status);
    o.digest = h.0;
    o
}

fn error_code(e: PlanError) -> u32 {
    PlanError::ALL
        .iter()
        .position(|&x| x == e)
        .map_or(u32::MAX, |p| p as u32 + 1)
}

/// Runs case `index` on the map currently loaded and prepared (see [`load`], [`prepare`]).
#[inline(never)]
pub fn run_case(s: &Site, storage: &mut Storage, index: usize) -> Outcome {
    let case = CASES[index];
    let Some(grid) = s.grid.as_ref().map(Grid::view) else {
        return Outcome {
            status: u32::MAX,
            ..Outcome::default()
        };
    };
    let (start, goal) = (s.start, s.goal);
    let mut o = Outcome::default();
    let mut h = Fnv::new();
    h.u32(index as u32);
    let result = match case.planner {
        Planner::AnyAngle => storage.anyangle(grid, start, goal).map(|st| {
            o.iterations = st.expanded;
            o.evaluations = st.pushed as u64;
            (
                st.length,
                st.optimum,
                st.optimum,
                path::turns(storage.path()) as u32,
                st.exact as u32,
            )
        }),
        Planner::Swarm(kind) => {
            // Stations half a cell off the corners the shortest route wraps: 42M instead of
            // 97M instructions for TCLHHO on the 40x40 map, 0.06% longer (see `guide_relax`).
            let params = PlanParams {
                seed: SEED,
                guide_relax: 0.5,
                ..PlanParams::new(kind)
            };
            let r = storage.plan(grid, start, goal, &params, PlanOptions::default());
            r.map(|r| {
                o.evaluations = r.evaluations;
                o.iterations = r.iterations;
                (
                    r.length,
                    r.initial_cost,
                    r.final_cost,
                    r.turns as u32,
                    r.best_iteration,
                )
            })
        }
    };
    match result {
        Ok((length, initial, final_cost, turns, best_iteration)) => {
            o.length_bits = length.to_bits();
            o.length_milli = (length * 1000.0) as u32;
            let out = storage.path();
            o.waypoints = out.len() as u32;
            o.valid = path::validate(grid, out, start, goal).is_ok() as u32;
            h.u32(0);
            h.u32(length.to_bits());
            h.u32(initial.to_bits());
            h.u32(final_cost.to_bits());
            h.u32(turns);
            h.u64(o.evaluations);
            h.u32(o.iterations);
            h.u32(best_iteration);
            h.u32(o.waypoints);
            for p in out.iter() {
                let Point { x, y } = *p;
                h.u32(x.to_bits());
                h.u32(y.to_bits());
            }
        }
        Err(e) => {
            o.status = error_code(e);
            h.u32(o.status);
        }
    }
    o.digest = h.0;
    o
}

/// The scenario digest: FNV-1a over the per-case digests, in case order.
pub fn combine(digests: &[u64]) -> u64 {
    let mut h = Fnv::new();
    for d in digests {
        h.u64(*d);
    }
    h.0
}

/// Route length the DWA loop drives (cells): the first stretch of the last plan, so that
/// the loop takes seconds, not minutes, under QEMU.
pub const DWA_ROUTE: f32 = 6.0;
/// Control steps at most (`dt` = 0.1 s).
pub const DWA_STEPS: u32 = 400;

/// The DWA control loop: a differential-drive robot (footprint radius 0.3 cells) follows the
/// first [`DWA_ROUTE`] cells of the A* route of the loaded map (cell centres keep half a cell
/// off the shelves; the swarm plans hug corners, which a local planner does not follow
/// without a clearance pass first) with the Dynamic Window
/// Approach, a person walking beside the route, at 10 Hz, until it arrives or
/// [`DWA_STEPS`] run out. The digest covers every commanded `(v, w)`, its mode and the
/// final pose. `status` is 0 when the robot arrived without touching a blocked cell;
/// `iterations` counts control steps, `evaluations` the window samples scored,
/// `length_milli` the driven distance, `waypoints` the route's points.
#[inline(never)]
pub fn dwa_control_loop(s: &Site, nodes: &mut Nodes) -> Option<Outcome> {
    let mut o = Outcome::default();
    let mut h = Fnv::new();
    h.u32(0xD3A);
    let grid = s.grid.as_ref()?.view();
    let (start, goal) = (s.start, s.goal);
    astar::plan(
        grid,
        start,
        goal,
        &mut nodes.nodes,
        &mut nodes.open,
        &mut nodes.route,
    )
    .ok()?;
    // The route: the A* path cut at DWA_ROUTE cells (a point on a clear segment).
    let mut route: Path<DWA_ROUTE_CAP> = Path::new();
    let mut travelled = 0.0f32;
    for (i, &p) in nodes.route.iter().enumerate() {
        if i > 0 {
            let prev = nodes.route[i - 1];
            let seg = prev.distance(p);
            if travelled + seg >= DWA_ROUTE {
                let t = (DWA_ROUTE - travelled) / seg;
                let _ = route.push(Point::new(
                    prev.x + t * (p.x - prev.x),
                    prev.y + t * (p.y - prev.y),
                ));
                break;
            }
            travelled += seg;
        }
        let _ = route.push(p);
    }
    if route.len() < 2 {
        return None;
    }
    let config = DwaConfig::default();
    let Ok(mut dwa) = Dwa::new(config) else {
        o.status = 1;
        return Some(o);
    };
    let (a, b) = (route[0], route[1]);
    let mut state = DwaState {
        x: a.x,
        y: a.y,
        theta: libm::atan2f(b.y - a.y, b.x - a.x),
        v: 0.0,
        w: 0.0,
    };
    // A person walking along the route's first leg, two cells to its side, at 0.4 cells/s.
    let (dx, dy) = ((b.x - a.x) / a.distance(b), (b.y - a.y) / a.distance(b));
    let mut person = DynamicDisc {
        x: a.x - 2.0 * dy,
        y: a.y + 2.0 * dx,
        r: 0.3,
        vx: 0.4 * dx,
        vy: 0.4 * dy,
    };
    let (mut arrived, mut collisions, mut driven) = (false, 0u32, 0.0f32);
    while o.iterations < DWA_STEPS {
        let cmd = match dwa.step(&state, grid, &[person], &route) {
            Ok(c) => c,
            Err(_) => {
                o.status = 2;
                break;
            }
        };
        o.iterations += 1;
        o.evaluations += cmd.samples as u64;
        h.u32(cmd.v.to_bits());
        h.u32(cmd.w.to_bits());
        h.u32(cmd.mode as u32);
        if cmd.mode == Mode::Arrived {
            arrived = true;
            break;
        }
        // Unicycle kinematics over one control period.
        let dt = config.dt;
        state.v = cmd.v;
        state.w = cmd.w;
        state.theta += cmd.w * dt;
        let (x0, y0) = (state.x, state.y);
        state.x += cmd.v * libm::cosf(state.theta) * dt;
        state.y += cmd.v * libm::sinf(state.theta) * dt;
        driven += Point::new(x0, y0).distance(state.position());
        person.x += person.vx * dt;
        person.y += person.vy * dt;
        if point_clearance(grid, state.position(), config.radius) < config.radius {
            collisions += 1;
        }
    }
    if o.status == 0 && !(arrived && collisions == 0) {
        o.status = 1;
    }
    o.valid = u32::from(arrived && collisions == 0);
    o.waypoints = route.len() as u32;
    o.length_milli = (driven * 1000.0) as u32;
    o.length_bits = driven.to_bits();
    for v in [state.x, state.y, state.theta] {
        h.u32(v.to_bits());
    }
    h.u32(o.status);
    h.u32(o.iterations);
    h.u32(collisions);
    o.digest = h.0;
    Some(o)
}
