//! The firmware scenario, shared verbatim by the MCU image (`main.rs`) and the host test
//! (`tests/tests/firmware_digest.rs` includes this file with `#[path]`), so both compute the
//! same plans and the same digest.
//!
//! Plans: A*, TCLHHO and IGWO (population 30, 500 iterations, corridor encoding, seed
//! [`SEED`]) on seed 000's 40x40 warehouse and on a 64x64 warehouse, all state in one
//! [`Storage`] (a `static` on the MCU) with capacity 64x64 cells, population 30, dimension 64.
//!
//! Digest: FNV-1a (64 bit) over the little-endian bytes of, per case: the case index, the
//! status (0 = ok, else 1 + the `PlanError` code), the path length, initial and final cost
//! (`f32::to_bits`), turns, evaluations, iterations, best iteration, the waypoint count and
//! every waypoint's `x` and `y` bits. Only integers are printed (no float formatting).

use planner_core::encoding::corridor::Station;
use planner_core::geometry::Cell;
use planner_core::grid::{Grid, words_for};
use planner_core::maps::{MapKind, seed000};
use planner_core::optim::any::AlgorithmKind;
use planner_core::optim::gwo::Gwo;
use planner_core::optim::hho::Hho;
use planner_core::path::{self, Path};
use planner_core::planner::{PlanParams, Workspace, plan};
use planner_core::search::{SearchNode, astar};
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
/// The seed of every stochastic plan.
pub const SEED: u64 = 0x5EED_0008;

/// A* search nodes, one per cell of the capacity: all-zero bytes, so a `static` of them is
/// in `.bss` (kept apart from [`Storage`], whose non-zero parts put it in `.data`).
pub type Nodes = [SearchNode; CELLS];

/// The rest of the planner state, sized for the capacity above. `const fn new` so that it can
/// be a `static` (built at link time, no large temporary on the stack).
pub struct Storage {
    /// The current map.
    pub grid: Grid<WORDS>,
    /// Its start and goal.
    pub start: Cell,
    /// Goal.
    pub goal: Cell,
    /// Guide route of the corridor encoding.
    pub guide: Path<PATH_CAP>,
    /// The plan's result.
    pub out: Path<PATH_CAP>,
    /// Walk-encoding bitset (unused by these plans, required by the workspace).
    pub visited: [u32; CELLS / 32 + 1],
    /// Corridor stations.
    pub stations: [Station; DIM],
    /// TCLHHO state.
    pub hho: Hho<POP, DIM>,
    /// IGWO state.
    pub gwo: Gwo<POP, DIM>,
}

impl Storage {
    /// Empty storage (an all-free 1x1 map until [`load`] runs).
    pub const fn new() -> Self {
        Storage {
            grid: match Grid::new(1, 1) {
                Ok(g) => g,
                Err(_) => panic!("1x1 grid"),
            },
            start: Cell::new(0, 0),
            goal: Cell::new(0, 0),
            guide: Path::new(),
            out: Path::new(),
            visited: [0; CELLS / 32 + 1],
            stations: [Station::EMPTY; DIM],
            hho: Hho::unconfigured(),
            gwo: Gwo::unconfigured(),
        }
    }
}

impl Default for Storage {
    fn default() -> Self {
        Self::new()
    }
}

/// The planners of the scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Planner {
    /// Exact A* (the reference).
    AStar,
    /// A swarm optimizer over the corridor encoding.
    Swarm(AlgorithmKind),
}

/// One plan of the scenario.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// Short name (printed).
    pub name: &'static str,
    /// Warehouse side length (seed 000 generator).
    pub side: usize,
    /// The planner.
    pub planner: Planner,
}

/// The plans, in order.
pub const CASES: [Case; 6] = [
    Case {
        name: "astar-40",
        side: 40,
        planner: Planner::AStar,
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
        name: "astar-64",
        side: 64,
        planner: Planner::AStar,
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
    /// Objective evaluations (0 for A*).
    pub evaluations: u64,
    /// Optimizer iterations (A*: cells expanded).
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

/// Loads the `side x side` seed 000 warehouse into `s` (not timed: the map would come from
/// flash or a radio on a robot).
pub fn load(s: &mut Storage, side: usize) -> Result<(), PlanError> {
    let map =
        seed000::<WORDS>(MapKind::Warehouse, side).map_err(|_| PlanError::CapacityExceeded)?;
    s.grid = map.grid;
    s.start = map.start;
    s.goal = map.goal;
    Ok(())
}

fn error_code(e: PlanError) -> u32 {
    PlanError::ALL
        .iter()
        .position(|&x| x == e)
        .map_or(u32::MAX, |p| p as u32 + 1)
}

/// Runs case `index` on the map currently loaded (see [`load`]).
pub fn run_case(s: &mut Storage, nodes: &mut Nodes, index: usize) -> Outcome {
    let case = CASES[index];
    let grid = s.grid.view();
    let (start, goal) = (s.start, s.goal);
    let mut o = Outcome::default();
    let mut h = Fnv::new();
    h.u32(index as u32);
    let result = match case.planner {
        Planner::AStar => astar::plan(grid, start, goal, nodes, &mut s.out).map(|st| {
            o.iterations = st.expanded;
            (
                st.length,
                st.length,
                st.length,
                path::turns(&s.out) as u32,
                0,
            )
        }),
        Planner::Swarm(kind) => {
            let params = PlanParams {
                seed: SEED,
                ..PlanParams::new(kind)
            };
            let mut ws = Workspace {
                nodes,
                guide: &mut s.guide,
                visited: &mut s.visited,
                stations: &mut s.stations,
            };
            let out = &mut s.out;
            let never = &mut || false;
            let r = match kind {
                AlgorithmKind::Hho | AlgorithmKind::Tclhho => plan(
                    grid,
                    start,
                    goal,
                    &params,
                    &mut ws,
                    &mut s.hho,
                    out,
                    &mut [],
                    never,
                ),
                _ => plan(
                    grid,
                    start,
                    goal,
                    &params,
                    &mut ws,
                    &mut s.gwo,
                    out,
                    &mut [],
                    never,
                ),
            };
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
            o.waypoints = s.out.len() as u32;
            o.valid = path::validate(grid, &s.out, start, goal).is_ok() as u32;
            h.u32(0);
            h.u32(length.to_bits());
            h.u32(initial.to_bits());
            h.u32(final_cost.to_bits());
            h.u32(turns);
            h.u64(o.evaluations);
            h.u32(o.iterations);
            h.u32(best_iteration);
            h.u32(o.waypoints);
            for p in s.out.iter() {
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

/// The DWA control loop of the issue: tracks the last planned path (`s.out`) with the
/// Dynamic Window Approach and reports the integer figures of the run (steps, final pose
/// bits, collisions) in an [`Outcome`] that joins the digest.
///
/// PENDING DWA: `planner_core::dwa` is being written in another branch. Until it is merged
/// this returns `None` (nothing joins the digest on either side). To add it: build the DWA
/// state in `Storage`, run the loop over `s.out` here, digest every commanded `(v, w)` and
/// the final pose with [`Fnv`], and return the outcome; `main.rs` and the host test already
/// time, print and digest whatever this returns.
pub fn dwa_control_loop(s: &mut Storage) -> Option<Outcome> {
    let _ = s;
    None
}
