//! Property tests across every planner of the crate (`PlannerKind::ALL`: A*, Theta*, ACO and
//! each swarm algorithm), without the `alloc` feature: caller-owned workspaces and the
//! firmware entry points `planner::plan`, `aco::plan`, `astar::plan` and `theta::plan`.
//!
//! The oracles are written here and share no code with the crate: a closed segment/square
//! intersection test in `f64` (Liang-Barsky clipping) for the collision rule, a king-move
//! checker for `Liu2020Igwo`'s loose walk rule, and a BFS over 4-connected free cells for
//! reachability (under the collision rule a diagonal step needs both side cells free, so
//! 8-connected reachability is 4-connectivity).
//!
//! - `every_planner_returns_valid_paths_or_exact_errors`: (a) an `Ok` path starts and ends
//!   at the requested centres and touches no blocked cell nor the map's outside; (c)
//!   `NoValidPath` exactly when BFS says unreachable, and a reachable goal is always found
//!   by A*, Theta* and the swarm planners on the corridor encoding (ACO may run out of
//!   budget); (d) no panic.
//! - `every_planner_is_deterministic_per_seed`: (b) two runs with the same seed and inputs
//!   give bit-identical paths and reports.
//! - `every_planner_reports_endpoint_errors`: (c) blocked or outside endpoints give the
//!   endpoint error of the documented order, for every planner.
//! - `reproduction_encodings_return_valid_paths`: (a) the column and walk encodings (both
//!   corner rules, pruning on and off): `Ok` paths are valid under their rule.

use std::collections::VecDeque;

use planner_core::PlanError;
use planner_core::encoding::corridor::Station;
use planner_core::encoding::walk::CornerRule;
use planner_core::geometry::{Cell, Point};
use planner_core::grid::{Grid, GridRef, words_for};
use planner_core::optim::any::AnyOptimizer;
use planner_core::path::Path;
use planner_core::planner::aco::{self, AcoParams, AcoWorkspace};
use planner_core::planner::{
    self, AnyAngleWorkspace, EncodingKind, InitKind, PlanOptions, PlanParams, PlanReport,
    PlanStorageMut, PlannerKind,
};
use planner_core::search::anyangle::{self, Link, Mesh, Node, Rect, Roots, Scratch};
use planner_core::search::astar::{AStarNode, OpenSlot};
use planner_core::search::{SearchNode, astar, connectivity, theta};
use proptest::prelude::*;
use proptest::test_runner::Config;

const SIDE: usize = 12;
const CELLS: usize = SIDE * SIDE;
type G = Grid<{ words_for(SIDE, SIDE) }>;
type Out = Path<{ CELLS + 8 }>;
/// Optimizer capacities: population and dimension.
const N: usize = 16;
const D: usize = 40;

#[derive(Clone, Debug)]
struct Map {
    w: usize,
    h: usize,
    blocked: Vec<bool>,
}

impl Map {
    fn blocked(&self, x: i64, y: i64) -> bool {
        x < 0
            || y < 0
            || x >= self.w as i64
            || y >= self.h as i64
            || self.blocked[y as usize * self.w + x as usize]
    }

    fn grid(&self) -> G {
        let mut g = G::new(self.w, self.h).unwrap();
        for y in 0..self.h {
            for x in 0..self.w {
                g.set_blocked(x, y, self.blocked[y * self.w + x]).unwrap();
            }
        }
        g
    }

    /// BFS over 4-connected free cells.
    fn reachable(&self, a: Cell, b: Cell) -> bool {
        let (w, h) = (self.w as i64, self.h as i64);
        let mut seen = vec![false; self.w * self.h];
        let mut queue = VecDeque::from([(a.x as i64, a.y as i64)]);
        seen[a.y as usize * self.w + a.x as usize] = true;
        while let Some((x, y)) = queue.pop_front() {
            if (x, y) == (b.x as i64, b.y as i64) {
                return true;
            }
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && nx < w && ny < h && !self.blocked(nx, ny) {
                    let i = ny as usize * self.w + nx as usize;
                    if !seen[i] {
                        seen[i] = true;
                        queue.push_back((nx, ny));
                    }
                }
            }
        }
        false
    }

    /// Whether the closed segment `a`-`b` meets the closed square of cell `(cx, cy)`.
    fn segment_meets_cell(a: Point, b: Point, cx: i64, cy: i64) -> bool {
        let (ax, ay) = (a.x as f64, a.y as f64);
        let (dx, dy) = (b.x as f64 - ax, b.y as f64 - ay);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q) in [
            (-dx, ax - (cx as f64 - 0.5)),
            (dx, (cx as f64 + 0.5) - ax),
            (-dy, ay - (cy as f64 - 0.5)),
            (dy, (cy as f64 + 0.5) - ay),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
        t0 <= t1
    }

    /// The collision rule: no segment touches a blocked cell or the outside of the map.
    fn path_is_clear(&self, path: &[Point]) -> bool {
        let segments: Vec<(Point, Point)> = match path {
            [p] => vec![(*p, *p)],
            _ => path.windows(2).map(|w| (w[0], w[1])).collect(),
        };
        segments.iter().all(|&(a, b)| {
            let lo_x = a.x.min(b.x).floor() as i64 - 1;
            let hi_x = a.x.max(b.x).ceil() as i64 + 1;
            let lo_y = a.y.min(b.y).floor() as i64 - 1;
            let hi_y = a.y.max(b.y).ceil() as i64 + 1;
            a.is_finite()
                && b.is_finite()
                && (lo_y..=hi_y).all(|y| {
                    (lo_x..=hi_x)
                        .all(|x| !self.blocked(x, y) || !Self::segment_meets_cell(a, b, x, y))
                })
        })
    }

    /// `Liu2020Igwo`'s loose walk: king moves between cell centres onto free cells; a diagonal
    /// is forbidden only when both side cells are blocked.
    fn loose_walk_is_valid(&self, path: &[Point]) -> bool {
        let integral = |p: &Point| p.x.fract() == 0.0 && p.y.fract() == 0.0;
        path.iter().all(integral)
            && path.iter().all(|p| !self.blocked(p.x as i64, p.y as i64))
            && path.windows(2).all(|w| {
                let (x, y) = (w[0].x as i64, w[0].y as i64);
                let (dx, dy) = (w[1].x as i64 - x, w[1].y as i64 - y);
                dx.abs() <= 1
                    && dy.abs() <= 1
                    && (dx, dy) != (0, 0)
                    && !(dx != 0 && dy != 0 && self.blocked(x + dx, y) && self.blocked(x, y + dy))
            })
    }
}

fn map_strategy() -> impl Strategy<Value = Map> {
    (2usize..=SIDE, 2usize..=SIDE, 0u32..45).prop_flat_map(|(w, h, density)| {
        proptest::collection::vec((0u32..100).prop_map(move |r| r < density), w * h)
            .prop_map(move |blocked| Map { w, h, blocked })
    })
}

/// A map and two free endpoints on it (when it has any free cell).
fn scenario() -> impl Strategy<Value = (Map, Cell, Cell, u64)> {
    (map_strategy(), any::<u16>(), any::<u16>(), any::<u64>()).prop_map(|(mut m, s, g, seed)| {
        let free: Vec<usize> = (0..m.w * m.h).filter(|&i| !m.blocked[i]).collect();
        let pick = |k: u16, m: &Map, free: &[usize]| -> usize {
            if free.is_empty() {
                k as usize % (m.w * m.h)
            } else {
                free[k as usize % free.len()]
            }
        };
        let (si, gi) = (pick(s, &m, &free), pick(g, &m, &free));
        m.blocked[si] = false;
        m.blocked[gi] = false;
        let cell = |i: usize| Cell::new((i % m.w) as u16, (i / m.w) as u16);
        let (start, goal) = (cell(si), cell(gi));
        (m, start, goal, seed)
    })
}

/// What one planner returned: the path's bits and the report, for exact comparison.
#[derive(Debug, PartialEq)]
struct Run {
    result: Result<(Vec<(u32, u32)>, String), PlanError>,
}

fn swarm_params(kind: PlannerKind, seed: u64) -> PlanParams {
    let algorithm = match kind {
        PlannerKind::Swarm(a) => a,
        _ => planner_core::optim::any::AlgorithmKind::Tclhho,
    };
    PlanParams {
        population: 10,
        iterations: 8,
        seed,
        corridor_spacing: 3.0,
        corridor_radius: 2.0,
        ..PlanParams::new(algorithm)
    }
}

fn aco_params(seed: u64) -> AcoParams {
    AcoParams {
        ants: 4,
        iterations: 4,
        seed,
        ..AcoParams::default()
    }
}

/// Runs `kind` on the grid with fresh workspaces, returning the path and report.
fn run(
    grid: GridRef<'_>,
    kind: PlannerKind,
    start: Cell,
    goal: Cell,
    params: &PlanParams,
    aco_params: &AcoParams,
    out: &mut Out,
) -> Result<Option<PlanReport>, PlanError> {
    let mut nodes = [AStarNode::EMPTY; CELLS];
    // Fewer open slots than cells: a caller-chosen capacity, enough for these small maps.
    let mut open = [OpenSlot::EMPTY; CELLS / 2];
    match kind {
        PlannerKind::AStar => {
            astar::plan(grid, start, goal, &mut nodes, &mut open, out).map(|_| None)
        }
        PlannerKind::Theta => {
            let mut nodes = [SearchNode::EMPTY; CELLS];
            theta::plan(grid, start, goal, &mut nodes, out).map(|_| None)
        }
        PlannerKind::Aco => {
            let mut labels = [0u32; CELLS];
            connectivity::label(grid, &mut labels)?;
            let mut tau = [0.0f32; 8 * CELLS];
            let mut delta = [0.0f32; 8 * CELLS];
            let mut visited = [0u32; CELLS / 32 + 1];
            let mut tour = [0u32; CELLS];
            let mut best = [0u32; CELLS];
            let mut ws = AcoWorkspace {
                tau: &mut tau,
                delta: &mut delta,
                visited: &mut visited,
                tour: &mut tour,
                best: &mut best,
                labels: &labels,
            };
            aco::plan(grid, start, goal, aco_params, &mut ws, out, &mut []).map(Some)
        }
        PlannerKind::AnyAngle => {
            let (mut rects, mut links) = (vec![Rect::EMPTY; CELLS], vec![Link::EMPTY; 2 * CELLS]);
            let mesh = Mesh::build(grid, &mut rects, &mut links)?;
            let (mut roots, mut search) = (vec![Roots::EMPTY; CELLS], vec![Node::EMPTY; 4 * CELLS]);
            let scratch = Scratch {
                roots: &mut roots,
                open: &mut search,
            };
            anyangle::plan(grid, &mesh, start, goal, scratch, out).map(|_| None)
        }
        PlannerKind::Swarm(_) => {
            let mut guide: Path<{ CELLS + 8 }> = Path::new();
            let mut visited = [0u32; CELLS / 32 + 1];
            let mut stations = [Station::EMPTY; D];
            let (mut rects, mut links) = (vec![Rect::EMPTY; CELLS], vec![Link::EMPTY; 2 * CELLS]);
            let mesh = Mesh::build(grid, &mut rects, &mut links)?;
            let (mut roots, mut search) = (vec![Roots::EMPTY; CELLS], vec![Node::EMPTY; 4 * CELLS]);
            let mut history = [0.0f32; 16];
            // Boxed: the optimizer state of a swarm does not belong on a test thread's stack.
            let mut optimizer = Box::new(AnyOptimizer::<N, D>::unconfigured());
            let mut ws = PlanStorageMut {
                anyangle: Some(AnyAngleWorkspace {
                    mesh,
                    scratch: Scratch {
                        roots: &mut roots,
                        open: &mut search,
                    },
                }),
                nodes: &mut nodes,
                open: &mut open,
                theta: &mut [],
                guide: &mut guide,
                visited: &mut visited,
                stations: &mut stations,
                optimizer: &mut *optimizer,
                out,
            };
            let options = PlanOptions {
                history: &mut history,
                interrupt: None,
            };
            planner::plan::<N, D, _>(grid, start, goal, params, &mut ws, options).map(Some)
        }
    }
}

fn record(result: Result<Option<PlanReport>, PlanError>, out: &Out) -> Run {
    Run {
        result: result.map(|report| {
            (
                out.iter().map(|p| (p.x.to_bits(), p.y.to_bits())).collect(),
                format!("{report:?}"),
            )
        }),
    }
}

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config(96))]

    #[test]
    fn every_planner_returns_valid_paths_or_exact_errors((map, start, goal, seed) in scenario()) {
        let g = map.grid();
        let reachable = map.reachable(start, goal);
        for kind in PlannerKind::ALL {
            let mut out = Out::new();
            let params = swarm_params(kind, seed);
            let result = run(g.view(), kind, start, goal, &params, &aco_params(seed), &mut out);
            match result {
                Ok(_) => {
                    prop_assert!(reachable, "{kind:?}: a path to an unreachable goal");
                    prop_assert_eq!(out.first(), Some(&start.center()), "{:?}", kind);
                    prop_assert_eq!(out.last(), Some(&goal.center()), "{:?}", kind);
                    prop_assert!(map.path_is_clear(&out), "{kind:?}: collision in {out:?}");
                }
                Err(PlanError::NoValidPath) => {
                    prop_assert!(!reachable, "{kind:?}: NoValidPath on a reachable goal");
                }
                Err(PlanError::BudgetExhausted) if kind == PlannerKind::Aco => {
                    prop_assert!(reachable);
                }
                Err(e) => prop_assert!(false, "{kind:?}: unexpected {e:?}"),
            }
        }
    }

    #[test]
    fn every_planner_is_deterministic_per_seed((map, start, goal, seed) in scenario()) {
        let g = map.grid();
        for kind in PlannerKind::ALL {
            let params = swarm_params(kind, seed);
            let aco = aco_params(seed);
            let mut first = Out::new();
            let a = run(g.view(), kind, start, goal, &params, &aco, &mut first);
            let a = record(a, &first);
            let mut second = Out::new();
            // Leave garbage in the output buffer: it must not leak into the result.
            second.push(Point::new(-7.0, 3.5)).unwrap();
            let b = run(g.view(), kind, start, goal, &params, &aco, &mut second);
            let b = record(b, &second);
            prop_assert_eq!(a, b, "{:?}", kind);
        }
    }

    #[test]
    fn every_planner_reports_endpoint_errors(
        (map, start, goal, seed) in scenario(),
        block_start in any::<bool>(),
        block_goal in any::<bool>(),
        start_out in proptest::option::of((0u16..3, 0u16..3)),
        goal_out in proptest::option::of((0u16..3, 0u16..3)),
    ) {
        let mut map = map;
        let idx = |c: Cell| c.y as usize * map.w + c.x as usize;
        if block_start {
            let i = idx(start);
            map.blocked[i] = true;
        }
        if block_goal {
            let i = idx(goal);
            map.blocked[i] = true;
        }
        let shift = |c: Cell, o: Option<(u16, u16)>, w: usize, h: usize| match o {
            // Outside on x (right of the map) or y (below), or far away.
            Some((0, k)) => Cell::new(w as u16 + k, c.y),
            Some((1, k)) => Cell::new(c.x, h as u16 + k),
            Some(_) => Cell::new(u16::MAX, u16::MAX),
            None => c,
        };
        let s = shift(start, start_out, map.w, map.h);
        let t = shift(goal, goal_out, map.w, map.h);
        let inside = |c: Cell| (c.x as usize) < map.w && (c.y as usize) < map.h;
        let expected = if !inside(s) {
            Some(PlanError::StartOutsideMap)
        } else if !inside(t) {
            Some(PlanError::GoalOutsideMap)
        } else if map.blocked[idx(s)] {
            Some(PlanError::StartOccupied)
        } else if map.blocked[idx(t)] {
            Some(PlanError::GoalOccupied)
        } else {
            None
        };
        let g = map.grid();
        for kind in PlannerKind::ALL {
            let mut out = Out::new();
            let r = run(g.view(), kind, s, t, &swarm_params(kind, seed), &aco_params(seed), &mut out);
            match expected {
                Some(e) => prop_assert_eq!(r.err(), Some(e), "{:?}", kind),
                None => prop_assert!(
                    !matches!(
                        r,
                        Err(PlanError::StartOutsideMap
                            | PlanError::GoalOutsideMap
                            | PlanError::StartOccupied
                            | PlanError::GoalOccupied)
                    ),
                    "{kind:?}: endpoint error on free endpoints"
                ),
            }
        }
    }

    #[test]
    fn reproduction_encodings_return_valid_paths(
        (map, start, goal, seed) in scenario(),
        algorithm in 0usize..9,
        variant in 0usize..6,
        prune in any::<bool>(),
    ) {
        let g = map.grid();
        let kind = PlannerKind::ALL[3 + algorithm];
        let (encoding, init, corner_rule) = [
            (EncodingKind::Column, InitKind::Optimizer, CornerRule::Strict),
            (EncodingKind::Column, InitKind::Diffusion, CornerRule::Strict),
            (EncodingKind::Walk, InitKind::Optimizer, CornerRule::Strict),
            (EncodingKind::Walk, InitKind::Optimizer, CornerRule::Loose),
            (EncodingKind::Corridor, InitKind::Optimizer, CornerRule::Strict),
            (EncodingKind::Walk, InitKind::Optimizer, CornerRule::Loose),
        ][variant];
        let params = PlanParams {
            encoding,
            init,
            corner_rule,
            prune,
            walk_steps: 30,
            ..swarm_params(kind, seed)
        };
        let reachable = map.reachable(start, goal);
        let mut out = Out::new();
        match run(g.view(), kind, start, goal, &params, &aco_params(seed), &mut out) {
            Ok(_) => {
                prop_assert_eq!(out.first(), Some(&start.center()));
                prop_assert_eq!(out.last(), Some(&goal.center()));
                let loose = encoding == EncodingKind::Walk && corner_rule == CornerRule::Loose;
                if loose {
                    prop_assert!(map.loose_walk_is_valid(&out), "{kind:?}: invalid walk {out:?}");
                } else {
                    prop_assert!(reachable);
                    prop_assert!(map.path_is_clear(&out), "{kind:?} {encoding:?}: collision in {out:?}");
                }
            }
            Err(PlanError::NoValidPath) => prop_assert!(!reachable, "{kind:?} {encoding:?}"),
            // Reproduction encodings may run out of budget, refuse maps they cannot
            // express (column: not x-monotone) or need more dimensions than D.
            Err(PlanError::BudgetExhausted | PlanError::InvalidParameters | PlanError::CapacityExceeded) => {
                prop_assert!(encoding != EncodingKind::Corridor);
            }
            Err(e) => prop_assert!(false, "{kind:?} {encoding:?}: unexpected {e:?}"),
        }
    }
}

/// The properties above are not vacuous: on an open map with a wall every planner finds a
/// valid path, and two planners of different kinds disagree on at least the report.
#[test]
fn every_planner_plans_on_a_walled_map() {
    let map = Map {
        w: 10,
        h: 6,
        blocked: (0..60).map(|i| i % 10 == 4 && i / 10 < 4).collect(),
    };
    let g = map.grid();
    let (start, goal) = (Cell::new(0, 0), Cell::new(9, 1));
    assert!(map.reachable(start, goal));
    for kind in PlannerKind::ALL {
        let mut out = Out::new();
        let r = run(
            g.view(),
            kind,
            start,
            goal,
            &swarm_params(kind, 7),
            &aco_params(7),
            &mut out,
        );
        let ok = r.is_ok() || (kind == PlannerKind::Aco && r == Err(PlanError::BudgetExhausted));
        assert!(ok, "{kind:?}: {r:?}");
        if r.is_ok() {
            assert!(map.path_is_clear(&out), "{kind:?}: {out:?}");
            // The oracle is strict: cutting the wall's corner is a collision.
            let mut cut = out.clone();
            cut.clear();
            cut.extend([Point::new(3.0, 5.0), Point::new(5.0, 3.0)]);
            assert!(!map.path_is_clear(&cut));
        }
    }
}
