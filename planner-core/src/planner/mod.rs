//! One planning API over every optimizer and encoding (the papers' planners), plus seed
//! 000's ant colony baseline in [`aco`].
//!
//! [`plan`] checks the endpoints, detects unreachable goals exactly (connectivity, before any
//! optimizer runs), builds the encoding, runs the optimizer, decodes its best point, applies
//! the patent's node pruning (collinear removal, then line-of-sight shortcutting) and
//! validates the result. It returns a path only if it is valid under the collision rule (or
//! under `Liu2020Igwo`'s looser rule when that reproduction option was asked for).
//!
//! [`PlanStorage`] holds everything a plan needs (capacities as constants, a zeroed
//! `static` in firmware); [`PlanStorageMut`] is the same as borrowed buffers, for storage sized
//! at run time:
//!
//! ```
//! use planner_core::{geometry::Cell, grid::{words_for, Grid}};
//! use planner_core::planner::{AlgorithmKind, PlanOptions, PlanParams, PlanStorage};
//!
//! let grid: Grid<{ words_for(12, 6) }> = Grid::parse_rows(
//!     b"............\n....@@@@....\n....@@@@....\n............\n..@@@@@@@@..\n............\n")?;
//! // Population 30, dimension 16, paths of 128 waypoints, mesh of 16 rectangles and 32
//! // links, 64 open any-angle nodes.
//! let mut storage = Box::new(PlanStorage::<30, 16, 128, 16, 32, 64>::new());
//! storage.prepare(grid.view())?; // once per map
//! let params = PlanParams { iterations: 60, ..PlanParams::new(AlgorithmKind::Tclhho) };
//! let report = storage.plan(grid.view(), Cell::new(0, 2), Cell::new(11, 3), &params, PlanOptions::default())?;
//! assert!(report.length <= report.initial_cost && storage.path().len() >= 2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod aco;
mod guide;
pub mod optimizers;
#[cfg(feature = "alloc")]
#[cfg_attr(docsrs, doc(cfg(feature = "alloc")))]
pub mod owned;
mod storage;

pub use crate::optim::any::AlgorithmKind;
pub use optimizers::{HhoOrGwo, PlanOptimizer};
pub use storage::PlanStorage;

use crate::encoding::Encoding;
pub use crate::encoding::blend::Blend;
use crate::encoding::column::ColumnEncoding;
use crate::encoding::corridor::{CorridorEncoding, Station};
use crate::encoding::walk::{CornerRule, WalkEncoding, validate_walk};
use crate::error::PlanError;
use crate::geometry::Cell;
use crate::grid::GridRef;
use crate::optim::random::Random;
use crate::optim::{Bounds, Objective, OptimError, Settings};
use crate::path::{self, PathView};
use crate::search::anyangle::{self, Mesh, Scratch};
use crate::search::astar::{self, AStarNode, OpenSlot};
use crate::search::{SearchNode, check_endpoints, theta as theta_star};

/// Every planner of the crate, by its command-line name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PlannerKind {
    /// A*, octile costs, no corner cutting (`astar`).
    AStar,
    /// Theta*, any-angle (`theta`).
    Theta,
    /// `Lei2024Warehouse`'s ant colony (`aco`).
    Aco,
    /// A swarm optimizer over an encoding ([`plan`]).
    Swarm(AlgorithmKind),
    /// The exact any-angle shortest path (`anyangle`, [`crate::search::anyangle`]).
    AnyAngle,
}

impl PlannerKind {
    /// Every planner, in a fixed order (also their wire codes' order).
    pub const ALL: [PlannerKind; 13] = [
        PlannerKind::AStar,
        PlannerKind::Theta,
        PlannerKind::Aco,
        PlannerKind::Swarm(AlgorithmKind::Tclhho),
        PlannerKind::Swarm(AlgorithmKind::Igwo),
        PlannerKind::Swarm(AlgorithmKind::Hho),
        PlannerKind::Swarm(AlgorithmKind::Gwo),
        PlannerKind::Swarm(AlgorithmKind::Tgwo),
        PlannerKind::Swarm(AlgorithmKind::Pso),
        PlannerKind::Swarm(AlgorithmKind::Ga),
        PlannerKind::Swarm(AlgorithmKind::Ssa),
        PlannerKind::Swarm(AlgorithmKind::SsaGwo),
        PlannerKind::AnyAngle,
    ];

    /// The command-line name (`astar`, `theta`, `aco`, `tclhho`, ...).
    pub fn name(self) -> &'static str {
        match self {
            PlannerKind::AStar => "astar",
            PlannerKind::Theta => "theta",
            PlannerKind::Aco => "aco",
            PlannerKind::Swarm(a) => a.name(),
            PlannerKind::AnyAngle => "anyangle",
        }
    }

    /// Whether the planner uses random numbers (the seed matters).
    pub fn is_stochastic(self) -> bool {
        !matches!(
            self,
            PlannerKind::AStar | PlannerKind::Theta | PlannerKind::AnyAngle
        )
    }
}

impl core::str::FromStr for PlannerKind {
    type Err = PlanError;

    /// Parses a name; an unknown one is [`PlanError::InvalidParameters`].
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        PlannerKind::ALL
            .iter()
            .copied()
            .find(|k| k.name().eq_ignore_ascii_case(s))
            .ok_or(PlanError::InvalidParameters)
    }
}

/// How a decision vector becomes a path (see [`crate::encoding`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum EncodingKind {
    /// The general encoding for any map (waypoints across an exact guide route).
    #[default]
    Corridor,
    /// `Lei2024Warehouse`'s column encoding (x-monotone paths only; reproduction mode).
    Column,
    /// `Liu2020Igwo`'s 8-connected walk (reproduction mode).
    Walk,
}

impl EncodingKind {
    /// `corridor`, `column` or `walk`.
    pub const fn name(self) -> &'static str {
        match self {
            EncodingKind::Corridor => "corridor",
            EncodingKind::Column => "column",
            EncodingKind::Walk => "walk",
        }
    }
}

/// The exact route the corridor encoding's stations sit on (it fixes the homotopy class the
/// optimizer searches in).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum GuideKind {
    /// The shortest any-angle path ([`crate::search::anyangle`]), so that the plan
    /// starts in the class of the shortest path. Needs [`PlanStorageMut::anyangle`].
    #[default]
    AnyAngle,
    /// The octile A* route. Many routes tie under octile costs, and the one A* keeps is often
    /// not in the class of the shortest any-angle path. Needs [`PlanStorageMut::nodes`] and
    /// [`PlanStorageMut::open`].
    AStar,
}

impl GuideKind {
    /// `anyangle` or `astar`.
    pub const fn name(self) -> &'static str {
        match self {
            GuideKind::AnyAngle => "anyangle",
            GuideKind::AStar => "astar",
        }
    }
}

/// The route a corridor plan's guide was made of ([`PlanReport::guide`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum GuideRoute {
    /// The shortest any-angle path.
    AnyAngle,
    /// The octile A* route (asked for, or the any-angle search ran past its bound).
    AStar,
    /// The Theta* route: a blended objective found it cheaper than the any-angle route
    /// ([`PlanStorageMut::theta`]).
    Theta,
}

impl GuideRoute {
    /// `anyangle`, `astar` or `theta`.
    pub const fn name(self) -> &'static str {
        match self {
            GuideRoute::AnyAngle => "anyangle",
            GuideRoute::AStar => "astar",
            GuideRoute::Theta => "theta",
        }
    }
}

/// Where the initial population comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum InitKind {
    /// The optimizer's own initialisation (uniform, or Tent for TCLHHO and TGWO).
    #[default]
    Optimizer,
    /// The patent's square-neighbourhood diffusion: rings of growing Chebyshev radius around
    /// the start; member `j` of a column-encoded path is a free cell of ring `j` in its
    /// column. Column encoding only.
    Diffusion,
}

/// Everything a plan needs besides the map and the endpoints.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PlanParams {
    /// The optimizer.
    pub algorithm: AlgorithmKind,
    /// The encoding.
    pub encoding: EncodingKind,
    /// Population size (the papers use 30).
    pub population: usize,
    /// Iteration horizon `T` (the papers use 500).
    pub iterations: u32,
    /// Stop after this many iterations without a relative improvement of
    /// [`STAGNATION_TOL`] (`None`: run to `T`).
    pub stagnation: Option<u32>,
    /// The seed.
    pub seed: u64,
    /// Initial population.
    pub init: InitKind,
    /// Apply the patent's node pruning to the result.
    pub prune: bool,
    /// Corner rule of the walk encoding (the other encodings always use SPEC's rule).
    pub corner_rule: CornerRule,
    /// Corridor encoding: the guide route.
    pub guide: GuideKind,
    /// Corridor encoding: how far (cells, per axis, at most) the any-angle guide's corners
    /// move off the obstacle corners they wrap before stations are placed on it. 0 keeps
    /// the shortest route itself, so that the plan ends at the shortest length; half a cell
    /// (to the free cell diagonal to each corner) makes evaluations cheaper, since fewer
    /// candidate legs graze an obstacle, and ends slightly longer (firmware: TCLHHO on the
    /// 40x40 warehouse takes 42M instead of 97M instructions and ends 0.06% longer).
    pub guide_relax: f32,
    /// Corridor encoding: guide length between stations (cells).
    pub corridor_spacing: f32,
    /// Corridor encoding: lateral reach of a waypoint (cells).
    pub corridor_radius: f32,
    /// Walk encoding: maximum steps (0: the capacity `D`).
    pub walk_steps: usize,
    /// Walk encoding: greediness of the step roulette.
    pub walk_beta: f32,
    /// Corridor encoding: what a path costs beyond its length (turns, missing clearance);
    /// [`Blend::LENGTH`], length alone, is the papers' objective (and the only one accepted
    /// without the `blend` feature).
    pub blend: Blend,
}

impl PlanParams {
    /// The host's defaults: the papers' population and horizon, stopping after
    /// [`HOST_STAGNATION`] iterations without improvement (on the generated 512 x 512
    /// warehouses of `host-sim bench scale` TCLHHO then takes a sixth of the time, to the
    /// same length). The firmware scenario and the papers' tables run every iteration.
    pub const fn host(algorithm: AlgorithmKind) -> Self {
        PlanParams {
            stagnation: Some(HOST_STAGNATION),
            ..PlanParams::new(algorithm)
        }
    }

    /// The papers' settings (population 30, 500 iterations) on the general encoding.
    pub const fn new(algorithm: AlgorithmKind) -> Self {
        PlanParams {
            algorithm,
            encoding: EncodingKind::Corridor,
            population: 30,
            iterations: 500,
            stagnation: None,
            seed: 0,
            init: InitKind::Optimizer,
            prune: true,
            corner_rule: CornerRule::Strict,
            guide: GuideKind::AnyAngle,
            guide_relax: 0.0,
            corridor_spacing: 8.0,
            corridor_radius: 5.0,
            walk_steps: 0,
            walk_beta: 2.0,
            blend: Blend::LENGTH,
        }
    }
}

/// The stagnation stop of the host's defaults ([`PlanParams::host`]): 50 iterations without
/// a relative improvement of [`STAGNATION_TOL`].
pub const HOST_STAGNATION: u32 = 50;

/// Why the optimizer stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PlanStop {
    /// The iteration horizon was reached.
    Iterations,
    /// No improvement for the configured number of iterations.
    Stagnation,
    /// The caller's interrupt hook asked to stop (deadline, cancellation): the best path
    /// so far is returned.
    Interrupted,
    /// Nothing to optimise (start equals goal, or the guide has no interior station).
    Trivial,
}

impl PlanStop {
    /// A short lower-case name.
    pub const fn name(self) -> &'static str {
        match self {
            PlanStop::Iterations => "iterations",
            PlanStop::Stagnation => "stagnation",
            PlanStop::Interrupted => "interrupted",
            PlanStop::Trivial => "trivial",
        }
    }
}

/// What [`plan`] reports besides the path.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PlanReport {
    /// Length of the returned path.
    pub length: f32,
    /// Direction changes of the returned path.
    pub turns: usize,
    /// The optimizer's best cost after initialisation (before any iteration).
    pub initial_cost: f32,
    /// The optimizer's final best cost (the decoded path before pruning).
    pub final_cost: f32,
    /// Objective evaluations, exactly.
    pub evaluations: u64,
    /// Iterations done.
    pub iterations: u32,
    /// First iteration whose best equals the final best (`Lei2024Warehouse`'s `I`).
    pub best_iteration: u32,
    /// Decision variables.
    pub dimension: usize,
    /// Why the optimizer stopped.
    pub stop: PlanStop,
    /// Entries written to the history buffer.
    pub history_len: usize,
    /// The corridor encoding's guide route: the any-angle route, the A* route when the
    /// any-angle search ran past its bound ([`ANYANGLE_GUIDE_CELLS_PER_NODE`]) or A* was
    /// asked for, or the Theta* route a blended objective preferred. `None` for the other
    /// encodings.
    #[cfg_attr(feature = "serde", serde(default))]
    pub guide: Option<GuideRoute>,
}

/// Everything [`plan`] works in, borrowed from the caller (no allocation happens inside):
/// the view of a [`PlanStorage`] (firmware, any capacity as constants) or of a host's
/// buffers sized at run time. `O` is the optimizer ([`PlanOptimizer`]).
pub struct PlanStorageMut<'a, O> {
    /// The map's mesh and a query's scratch for the any-angle guide
    /// ([`GuideKind::AnyAngle`]; `None` with that guide is
    /// [`PlanError::InvalidParameters`]).
    pub anyangle: Option<AnyAngleWorkspace<'a>>,
    /// One A* node per map cell, for the A* guide ([`GuideKind::AStar`]; other guides may
    /// pass an empty slice).
    pub nodes: &'a mut [AStarNode],
    /// The A* open list: [`astar::open_capacity`] slots never overflow; fewer are the
    /// caller's choice ([`PlanError::CapacityExceeded`] when a search outgrows them).
    pub open: &'a mut [OpenSlot],
    /// One Theta* node per map cell: with a blended objective (not length alone) the
    /// Theta* route is the guide when its blended cost is lower than the any-angle
    /// route's (it follows aisles with few turns where the shortest path zigzags across
    /// them). Empty: the any-angle route only.
    pub theta: &'a mut [SearchNode],
    /// The guide route of the corridor encoding (up to its capacity in waypoints).
    pub guide: &'a mut PathView,
    /// A bitset of `cells / 32 + 1` words for the walk encoding; other encodings never read
    /// it, so they may pass an empty slice (the walk encoding then fails with
    /// [`PlanError::CapacityExceeded`]).
    pub visited: &'a mut [u32],
    /// The stations of the corridor encoding: at least `D` for an optimizer of dimension
    /// capacity `D` (fewer are [`PlanError::CapacityExceeded`]).
    pub stations: &'a mut [Station],
    /// The optimizer, configured in place for the plan's algorithm.
    pub optimizer: &'a mut O,
    /// The planned path.
    pub out: &'a mut PathView,
}

/// How a plan reports its progress and may be stopped; [`PlanOptions::default`] asks for
/// neither.
#[derive(Default)]
pub struct PlanOptions<'a> {
    /// Receives the best cost per iteration while it has room.
    pub history: &'a mut [f32],
    /// Called once per iteration: `true` stops early with the best path so far (a deadline
    /// or a cancellation).
    pub interrupt: Option<&'a mut dyn FnMut() -> bool>,
}

/// What the any-angle guide needs: the map's mesh (built once per map) and a query's
/// scratch.
pub struct AnyAngleWorkspace<'a> {
    /// The mesh of the grid [`plan`] is given.
    pub mesh: Mesh<'a>,
    /// The search's scratch.
    pub scratch: Scratch<'a>,
}

/// The any-angle guide's search may expand one node per this many cells of the map (at
/// least [`ANYANGLE_GUIDE_MIN_NODES`]): an expansion costs about as much as four of A*'s, so
/// the bound keeps the guide within about A*'s time on large maps; past it the A* route is
/// the guide.
pub const ANYANGLE_GUIDE_CELLS_PER_NODE: usize = 4;

/// The any-angle guide's expansion budget on small maps: cluttered warehouses of a few
/// hundred cells a side need tens of thousands of expansions, and the A* route it would fall
/// back to is up to 2% longer.
pub const ANYANGLE_GUIDE_MIN_NODES: usize = 1 << 16;

/// Relative improvement below which an iteration counts as stagnant.
pub const STAGNATION_TOL: f32 = 1e-4;

fn optim_error(e: OptimError) -> PlanError {
    match e {
        OptimError::PopulationOutOfRange | OptimError::DimensionOutOfRange => {
            PlanError::CapacityExceeded
        }
        _ => PlanError::InvalidParameters,
    }
}

/// Plans `start -> goal` into `storage.out` with `storage.optimizer` (capacity `N` members
/// and `D` dimensions), which it configures for `params.algorithm`; `options` take the
/// per-iteration history and an interrupt.
///
/// Errors: the endpoint checks, [`PlanError::NoValidPath`] when the goal is unreachable
/// (exact, before optimising), [`PlanError::InvalidParameters`] for NaN or out-of-range
/// parameters and unsupported combinations, [`PlanError::CapacityExceeded`] when a buffer or
/// `N`/`D` is too small, [`PlanError::BudgetExhausted`] when a reproduction encoding ends
/// with an infeasible best (the papers' "—").
pub fn plan<const N: usize, const D: usize, O: PlanOptimizer<N, D>>(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    params: &PlanParams,
    storage: &mut PlanStorageMut<'_, O>,
    options: PlanOptions<'_>,
) -> Result<PlanReport, PlanError> {
    let PlanStorageMut {
        anyangle,
        nodes,
        open,
        theta,
        guide,
        visited,
        stations,
        optimizer,
        out,
    } = storage;
    let (optimizer, out) = (&mut **optimizer, &mut **out);
    let (nodes, open, guide) = (&mut **nodes, &mut **open, &mut **guide);
    let (visited, stations) = (&mut **visited, &mut **stations);
    let history = options.history;
    let mut never = || false;
    let interrupt: &mut dyn FnMut() -> bool = match options.interrupt {
        Some(f) => f,
        None => &mut never,
    };
    check_endpoints(grid, start, goal)?;
    check_params(params)?;
    let query = Query {
        grid,
        start,
        goal,
        params: *params,
    };
    // Checked here as well as by the optimizer, so that a query that needs no optimizing
    // (a straight guide) reports the same error as any other.
    if params.population > N {
        return Err(PlanError::CapacityExceeded);
    }
    // The guide route doubles as the exact reachability test: either search exhausts the
    // start's component before it reports NoValidPath.
    let guide_used = match params.guide {
        GuideKind::AnyAngle => {
            let aa = anyangle.as_mut().ok_or(PlanError::InvalidParameters)?;
            let scratch = Scratch {
                roots: &mut *aa.scratch.roots,
                open: &mut *aa.scratch.open,
            };
            // Found into `out` (free until the result is decoded), moved off the corners
            // it wraps, then resampled. Bounded to about A*'s work: on a dense lattice of
            // racks the exact search costs more than the route is worth, and the A* route
            // serves if the workspace has its state.
            let budget =
                (grid.cells() / ANYANGLE_GUIDE_CELLS_PER_NODE).max(ANYANGLE_GUIDE_MIN_NODES) as u32;
            match anyangle::plan_within(grid, &aa.mesh, start, goal, scratch, out, budget) {
                Ok(_) => {
                    guide::relax(grid, out, params.guide_relax);
                    let kind = if smoother_theta(grid, start, goal, params, theta, out, guide) {
                        GuideRoute::Theta
                    } else {
                        GuideRoute::AnyAngle
                    };
                    guide::resample(grid, out, guide);
                    kind
                }
                Err(PlanError::BudgetExhausted) if nodes.len() >= grid.cells() => {
                    astar::plan(grid, start, goal, nodes, open, guide)?;
                    GuideRoute::AStar
                }
                Err(e) => return Err(e),
            }
        }
        GuideKind::AStar => {
            astar::plan(grid, start, goal, nodes, open, guide)?;
            GuideRoute::AStar
        }
    };
    let mut report = match params.encoding {
        EncodingKind::Corridor => {
            if guide.len() <= 2 {
                return trivial(grid, guide, out);
            }
            // Stations include the two fixed ends, so at most D - 2 of them move.
            // One station per dimension: fewer would cap the plan's decision variables.
            let stations = stations.get_mut(..D).ok_or(PlanError::CapacityExceeded)?;
            let mut enc = CorridorEncoding::build(
                grid,
                guide,
                params.corridor_spacing,
                params.corridor_radius,
                D,
                stations,
            )?
            .with_blend(params.blend);
            if enc.dim() == 0 {
                return trivial(grid, guide, out);
            }
            optimise(query, &mut enc, None, optimizer, out, history, interrupt)
        }
        EncodingKind::Column => {
            let mut enc = ColumnEncoding::new(grid, start, goal)?;
            if enc.dim() > D {
                return Err(PlanError::CapacityExceeded);
            }
            optimise(query, &mut enc, None, optimizer, out, history, interrupt)
        }
        EncodingKind::Walk => {
            let steps = if params.walk_steps == 0 {
                D
            } else {
                params.walk_steps
            };
            if steps > D {
                return Err(PlanError::CapacityExceeded);
            }
            if start == goal {
                return trivial(grid, guide, out);
            }
            let rule = params.corner_rule;
            let mut enc =
                WalkEncoding::new(grid, start, goal, steps, rule, params.walk_beta, visited)?;
            optimise(
                query,
                &mut enc,
                Some(rule),
                optimizer,
                out,
                history,
                interrupt,
            )
        }
    }?;
    if params.encoding == EncodingKind::Corridor {
        report.guide = Some(guide_used);
    }
    Ok(report)
}

/// With a blended objective and Theta* nodes for the map: plans Theta* into `spare` and, if
/// its route (relaxed off corners like the any-angle one) costs less than `route` under the
/// blend, copies it into `route`. Returns whether it did.
fn smoother_theta(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    params: &PlanParams,
    theta: &mut [SearchNode],
    route: &mut PathView,
    spare: &mut PathView,
) -> bool {
    if !cfg!(feature = "blend") || params.blend.is_length() || theta.len() < grid.cells() {
        return false;
    }
    if theta_star::plan(grid, start, goal, theta, spare).is_err() {
        return false;
    }
    guide::relax(grid, spare, params.guide_relax);
    let blend = params.blend;
    if blend.path_cost(grid, spare) >= blend.path_cost(grid, route)
        || spare.len() > route.capacity()
    {
        return false;
    }
    route.clear();
    for p in spare.iter() {
        let _ = route.push(*p);
    }
    true
}

fn check_params(p: &PlanParams) -> Result<(), PlanError> {
    let finite_pos = |v: f32| v.is_finite() && v > 0.0;
    if p.population == 0
        || p.iterations == 0
        || p.stagnation == Some(0)
        || !finite_pos(p.corridor_spacing)
        || !(p.guide_relax.is_finite() && (0.0..=0.5).contains(&p.guide_relax))
        || !finite_pos(p.corridor_radius)
        || !(p.walk_beta.is_finite() && p.walk_beta >= 0.0)
        || !p.blend.is_valid()
    {
        return Err(PlanError::InvalidParameters);
    }
    if p.init == InitKind::Diffusion && p.encoding != EncodingKind::Column {
        return Err(PlanError::InvalidParameters);
    }
    // The reproduction encodings cost what the papers' tables count: length alone; without
    // the `blend` feature every encoding does.
    if !p.blend.is_length() && (p.encoding != EncodingKind::Corridor || !cfg!(feature = "blend")) {
        return Err(PlanError::InvalidParameters);
    }
    Ok(())
}

/// The guide itself (start equals goal, or goal adjacent): nothing to optimise.
fn trivial(
    grid: GridRef<'_>,
    guide: &PathView,
    out: &mut PathView,
) -> Result<PlanReport, PlanError> {
    out.clear();
    for p in guide.iter() {
        out.push(*p).map_err(|_| PlanError::CapacityExceeded)?;
    }
    let length = path::length(out);
    let _ = grid;
    Ok(PlanReport {
        length,
        turns: path::turns(out),
        initial_cost: length,
        final_cost: length,
        evaluations: 0,
        iterations: 0,
        best_iteration: 0,
        dimension: 0,
        stop: PlanStop::Trivial,
        history_len: 0,
        guide: None,
    })
}

/// What [`plan`] is asked: the map, the endpoints and the parameters.
#[derive(Clone, Copy)]
struct Query<'a> {
    grid: GridRef<'a>,
    start: Cell,
    goal: Cell,
    // A copy: a reference stored here lets the caller's parameters escape, and the firmware's
    // plan then keeps the column and walk encodings it never uses (13 KiB of flash).
    params: PlanParams,
}

/// Runs the optimizer over `enc` for `query`, then decodes, checks and prunes its best path
/// into `out` (`walk_rule`: the walk encoding's validity rule, for the walk encoding).
fn optimise<const N: usize, const D: usize, E: Encoding, O: PlanOptimizer<N, D>>(
    query: Query<'_>,
    enc: &mut E,
    walk_rule: Option<CornerRule>,
    opt: &mut O,
    out: &mut PathView,
    history: &mut [f32],
    interrupt: &mut dyn FnMut() -> bool,
) -> Result<PlanReport, PlanError> {
    let Query {
        grid,
        start,
        goal,
        ref params,
    } = query;
    let dim = enc.dim();
    if dim == 0 || dim > D {
        return Err(PlanError::CapacityExceeded);
    }
    let bounds = Bounds::<D>::from_fn(dim, |i| enc.bounds(i)).map_err(optim_error)?;
    let settings = Settings {
        population: params.population,
        iterations: params.iterations,
        seed: params.seed,
    };
    opt.configure_kind(params.algorithm, settings, &bounds)
        .map_err(optim_error)?;
    let mut objective = crate::encoding::Costs(enc);
    match params.init {
        InitKind::Optimizer => opt.init(&mut objective, None),
        InitKind::Diffusion => {
            diffusion_init::<N, D, _, _>(grid, start, params, dim, opt, &mut objective)
        }
    }
    .map_err(optim_error)?;
    let initial_cost = opt.best_cost();
    let mut written = 0;
    // Stagnation counts iterations without a *relative* improvement of STAGNATION_TOL: the
    // Cauchy and Levy moves keep shaving off micro-units long after the path has settled.
    let (mut settled_cost, mut settled_at) = (initial_cost, 0u32);
    let stop = loop {
        if opt.iteration() >= params.iterations {
            break PlanStop::Iterations;
        }
        if opt.best_cost() < settled_cost * (1.0 - STAGNATION_TOL) {
            (settled_cost, settled_at) = (opt.best_cost(), opt.iteration());
        }
        if params
            .stagnation
            .is_some_and(|k| opt.iteration() - settled_at >= k)
        {
            break PlanStop::Stagnation;
        }
        if interrupt() {
            break PlanStop::Interrupted;
        }
        opt.step(&mut objective).map_err(optim_error)?;
        if let Some(slot) = history.get_mut(written) {
            *slot = opt.best_cost();
            written += 1;
        }
    };
    let final_cost = opt.best_cost();
    objective.0.decode(opt.best_position(), out)?;
    let valid = match walk_rule {
        Some(rule) => {
            validate_walk(grid, out, rule)
                && out.first() == Some(&start.center())
                && out.last() == Some(&goal.center())
        }
        None => path::validate(grid, out, start, goal).is_ok(),
    };
    if !valid {
        // Decoders only emit valid paths; refuse rather than hand out an invalid one.
        return Err(PlanError::NoValidPath);
    }
    if params.prune && walk_rule != Some(CornerRule::Loose) {
        path::prune_collinear(out);
        if !cfg!(feature = "blend") || params.blend.is_length() {
            path::shortcut(grid, out);
        } else {
            // Shortcuts would cut the margins away: only those that lower the blend, then
            // the waypoints polished into place and freed of the ones that turned redundant.
            params.blend.simplify(grid, out);
            params.blend.polish(grid, out);
            params.blend.simplify(grid, out);
        }
    }
    Ok(PlanReport {
        length: path::length(out),
        turns: path::turns(out),
        initial_cost,
        final_cost,
        evaluations: opt.evaluations(),
        iterations: opt.iteration(),
        best_iteration: opt.best_iteration(),
        dimension: dim,
        stop,
        history_len: written,
        guide: None,
    })
}

/// Initialises `opt` from [`diffusion_rows`]. Out of line so that the rows (`N D` floats)
/// take stack only in the plans that ask for this initialisation.
#[inline(never)]
fn diffusion_init<const N: usize, const D: usize, O: PlanOptimizer<N, D>, F: Objective + ?Sized>(
    grid: GridRef<'_>,
    start: Cell,
    params: &PlanParams,
    dim: usize,
    opt: &mut O,
    objective: &mut F,
) -> Result<(), OptimError> {
    let mut rows = [[0.0f32; D]; N];
    let count = params.population.min(N);
    diffusion_rows(grid, start, &mut rows[..count], dim, params.seed);
    let mut refs: [&[f32]; N] = [&[]; N];
    for (r, row) in refs.iter_mut().zip(rows.iter()).take(count) {
        *r = &row[..dim];
    }
    opt.init(objective, Some(&refs[..count]))
}

/// The patent's square-neighbourhood diffusion for the column encoding: row `j` is a free
/// row of column `start.x + j` within Chebyshev radius `j` of the start (the ring's edge in
/// that column), drawn uniformly; a column with none keeps the start row.
fn diffusion_rows<const D: usize>(
    grid: GridRef<'_>,
    start: Cell,
    rows: &mut [[f32; D]],
    dim: usize,
    seed: u64,
) {
    let mut rng = Random::new(seed ^ 0xD1FF_0510);
    for row in rows.iter_mut() {
        for (j, v) in row.iter_mut().enumerate().take(dim) {
            let x = start.x as isize + j as isize;
            let lo = (start.y as isize - j as isize).max(0);
            let hi = (start.y as isize + j as isize).min(grid.height() as isize - 1);
            let free = (lo..=hi).filter(|&y| !grid.is_blocked(x, y)).count();
            *v = start.y as f32;
            if free > 0 {
                let pick = rng.index(free);
                if let Some(y) = (lo..=hi).filter(|&y| !grid.is_blocked(x, y)).nth(pick) {
                    *v = y as f32;
                }
            }
        }
    }
}

// The tests plan on the papers' maps.
#[cfg(all(test, feature = "maps"))]
mod tests;
