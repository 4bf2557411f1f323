//! The firmware scenario, shared verbatim by the MCU image (`main.rs`) and the host test
//! (`tests/tests/firmware_digest.rs` includes this file with `#[path]`), so both compute the
//! same plans and the same digest.
//!
//! Plans: the exact any-angle planner, TCLHHO and IGWO (population 30, 500 iterations,
//! corridor encoding on the any-angle guide, seed [`SEED`]) on seed 000's 40x40 warehouse
//! and on a 64x64 warehouse, state in [`Storage`] (map, paths, optimizer) and
//! [`AnyAngleState`] (the map's mesh, built by [`load`], and a query's scratch), both
//! `static`s on the MCU, with capacity 64x64 cells, population 30, dimension 64. The DWA
//! loop follows an A* route, with [`Nodes`] in the memory the any-angle state used (the
//! MCU shares it; the phases never overlap).
//!
//! Digest: FNV-1a (64 bit) over the little-endian bytes of, per case: the case index, the
//! status (0 = ok, else 1 + the `PlanError` code), the path length, initial and final cost
//! (`f32::to_bits`), turns, evaluations, iterations, best iteration, the waypoint count and
//! every waypoint's `x` and `y` bits. Only integers are printed (no float formatting).

use planner_core::dwa::{Dwa, DwaConfig, DwaState, DynamicDisc, Mode, point_clearance};
use planner_core::encoding::corridor::Station;
use planner_core::geometry::Cell;
use planner_core::grid::{Grid, words_for};
use planner_core::maps::{MapKind, seed000};
use planner_core::optim::any::AlgorithmKind;
use planner_core::optim::gwo::Gwo;
use planner_core::optim::hho::Hho;
use planner_core::optim::{Bounds, Objective, OptimError, Optimizer, Settings};
use planner_core::path::{self, Path};
use planner_core::planner::{AnyAngleWorkspace, PlanOptimizer, PlanParams, Workspace, plan};
use planner_core::search::anyangle::{self, MeshStorage, QueryStorage};
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

/// The any-angle planner's state: the loaded map's mesh and a query's scratch (32 bytes a
/// rectangle and a node). All-zero bytes, so a `static` of it is in `.bss`.
pub struct AnyAngleState {
    /// The mesh of the loaded map (built by [`load`]).
    pub mesh: MeshStorage<RECTS, LINKS>,
    /// Roots and open list.
    pub query: QueryStorage<RECTS, SEARCH_OPEN>,
}

impl AnyAngleState {
    /// Fresh state.
    pub const fn new() -> Self {
        AnyAngleState {
            mesh: MeshStorage::new(),
            query: QueryStorage::new(),
        }
    }
}

impl Default for AnyAngleState {
    fn default() -> Self {
        Self::new()
    }
}

/// A* search state for the DWA loop's route: a node per cell of the capacity (4 bytes) and
/// [`OPEN`] open-list slots (12 bytes). All-zero bytes, so a `static` of it is in `.bss`.
pub struct Nodes {
    /// One per cell.
    pub nodes: [AStarNode; CELLS],
    /// The open list.
    pub open: [OpenSlot; OPEN],
}

impl Nodes {
    /// Fresh search state.
    pub const fn new() -> Self {
        Nodes {
            nodes: [AStarNode::EMPTY; CELLS],
            open: [OpenSlot::EMPTY; OPEN],
        }
    }
}

impl Default for Nodes {
    fn default() -> Self {
        Self::new()
    }
}

/// The one optimizer state of the scenario: TCLHHO and IGWO never run at the same time, so
/// they share the storage of the larger (`AnyOptimizer` would hold PSO's three times larger
/// state). Switching family replaces the variant in place.
#[allow(clippy::large_enum_variant)]
pub enum Swarm {
    /// HHO or TCLHHO.
    Hho(Hho<POP, DIM>),
    /// GWO, TGWO or IGWO.
    Gwo(Gwo<POP, DIM>),
}

macro_rules! swarm {
    ($self:ident, $o:ident => $e:expr) => {
        match $self {
            Swarm::Hho($o) => $e,
            Swarm::Gwo($o) => $e,
        }
    };
}

impl Optimizer for Swarm {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        swarm!(self, o => o.init(objective, initial))
    }
    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        swarm!(self, o => o.step(objective))
    }
    fn best_position(&self) -> &[f32] {
        swarm!(self, o => o.best_position())
    }
    fn best_cost(&self) -> f32 {
        swarm!(self, o => o.best_cost())
    }
    fn iteration(&self) -> u32 {
        swarm!(self, o => o.iteration())
    }
    fn evaluations(&self) -> u64 {
        swarm!(self, o => o.evaluations())
    }
    fn best_iteration(&self) -> u32 {
        swarm!(self, o => o.best_iteration())
    }
    fn horizon(&self) -> u32 {
        swarm!(self, o => o.horizon())
    }
}

impl PlanOptimizer<POP, DIM> for Swarm {
    fn configure_kind(
        &mut self,
        kind: AlgorithmKind,
        settings: Settings,
        bounds: &Bounds<DIM>,
    ) -> Result<(), OptimError> {
        // Assigned from constants: the value is copied from flash into place, where
        // `Swarm::Gwo(Gwo::unconfigured())` built a 9 KiB temporary on the stack first.
        const HHO: Swarm = Swarm::Hho(Hho::unconfigured());
        const GWO: Swarm = Swarm::Gwo(Gwo::unconfigured());
        let hho = matches!(kind, AlgorithmKind::Hho | AlgorithmKind::Tclhho);
        match self {
            Swarm::Hho(_) if !hho => *self = GWO,
            Swarm::Gwo(_) if hho => *self = HHO,
            _ => {}
        }
        swarm!(self, o => o.configure_kind(kind, settings, bounds))
    }
}

/// The rest of the planner state, sized for the capacity above. `const fn new` so that it can
/// be a `static` (built at link time, no large temporary on the stack).
pub struct Storage {
    /// The current map (`None` until [`load`]: a `Some` placeholder would be the only
    /// non-zero bytes of the firmware's `static`, which would then be copied from an 18 KiB
    /// flash image instead of zeroed in `.bss`).
    pub grid: Option<Grid<WORDS>>,
    /// Its start and goal.
    pub start: Cell,
    /// Goal.
    pub goal: Cell,
    /// Guide route of the corridor encoding.
    pub guide: Path<PATH_CAP>,
    /// The plan's result.
    pub out: Path<PATH_CAP>,
    /// Corridor stations.
    pub stations: [Station; DIM],
    /// TCLHHO or IGWO state.
    pub swarm: Swarm,
}

impl Storage {
    /// Empty storage (no map until [`load`] runs), all zero bytes.
    pub const fn new() -> Self {
        Storage {
            grid: None,
            start: Cell::new(0, 0),
            goal: Cell::new(0, 0),
            guide: Path::new(),
            out: Path::new(),
            stations: [Station::EMPTY; DIM],
            swarm: Swarm::Hho(Hho::unconfigured()),
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
    /// Warehouse side length (seed 000 generator).
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

/// Loads the `side x side` seed 000 warehouse into `s` (not timed: the map would come from
/// flash or a radio on a robot).
///
/// Out of line, like [`run_case`] and [`dwa_control_loop`]: the map generator takes about
/// 5 KiB of stack, which inlined into `main` stayed reserved through every plan (peak stack
/// 8.4 KiB instead of 6.0 KiB).
#[inline(never)]
pub fn load(s: &mut Storage, side: usize) -> Result<(), PlanError> {
    let map =
        seed000::<WORDS>(MapKind::Warehouse, side).map_err(|_| PlanError::CapacityExceeded)?;
    s.grid = Some(map.grid);
    s.start = map.start;
    s.goal = map.goal;
    Ok(())
}

/// Builds the loaded map's any-angle mesh (once per map, timed on its own); the outcome's
/// `iterations` and `waypoints` are the rectangles and links.
#[inline(never)]
pub fn prepare(s: &Storage, aa: &mut AnyAngleState) -> Outcome {
    let mut o = Outcome::default();
    let mut h = Fnv::new();
    h.u32(0x3E5);
    match s.grid.as_ref().map(|g| aa.mesh.build(g.view())) {
        Some(Ok(mesh)) => {
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
pub fn run_case(s: &mut Storage, aa: &mut AnyAngleState, index: usize) -> Outcome {
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
    let mesh = aa.mesh.mesh();
    let result = match case.planner {
        Planner::AnyAngle => {
            anyangle::plan(grid, &mesh, start, goal, aa.query.scratch(), &mut s.out).map(|st| {
                o.iterations = st.expanded;
                o.evaluations = st.pushed as u64;
                (
                    st.length,
                    st.optimum,
                    st.optimum,
                    path::turns(&s.out) as u32,
                    st.exact as u32,
                )
            })
        }
        Planner::Swarm(kind) => {
            // Stations half a cell off the corners the shortest route wraps: 42M instead of
            // 97M instructions for TCLHHO on the 40x40 map, 0.06% longer (see `guide_relax`).
            let params = PlanParams {
                seed: SEED,
                guide_relax: 0.5,
                ..PlanParams::new(kind)
            };
            // The any-angle guide needs no A* state, and the corridor encoding no walk
            // bitset.
            let mut ws = Workspace {
                anyangle: Some(AnyAngleWorkspace {
                    mesh,
                    scratch: aa.query.scratch(),
                }),
                nodes: &mut [],
                open: &mut [],
                guide: &mut s.guide,
                visited: &mut [],
                stations: &mut s.stations,
            };
            let r = plan(
                grid,
                start,
                goal,
                &params,
                &mut ws,
                &mut s.swarm,
                &mut s.out,
                &mut [],
                &mut || false,
            );
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
pub fn dwa_control_loop(s: &mut Storage, nodes: &mut Nodes) -> Option<Outcome> {
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
        &mut s.out,
    )
    .ok()?;
    // The route: the A* path cut at DWA_ROUTE cells (a point on a clear segment).
    let mut route: Path<DWA_ROUTE_CAP> = Path::new();
    let mut walked = 0.0f32;
    for (i, &p) in s.out.iter().enumerate() {
        if i > 0 {
            let prev = s.out[i - 1];
            let seg = prev.distance(p);
            if walked + seg >= DWA_ROUTE {
                let t = (DWA_ROUTE - walked) / seg;
                let _ = route.push(Point::new(
                    prev.x + t * (p.x - prev.x),
                    prev.y + t * (p.y - prev.y),
                ));
                break;
            }
            walked += seg;
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
